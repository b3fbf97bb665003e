#include "engine/pair_bounds.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace invmap::engine {

BoxPairBound::BoxPairBound(const kernels::RigidMotion& bIntoA) {
  identity_ = true;
  for (int k = 0; k < 3; ++k) {
    translation_[k] = bIntoA.translation[k];
    for (int l = 0; l < 3; ++l) {
      rotation_[k][l] = bIntoA.rotation[k][l];
      absRotation_[k][l] = std::abs(rotation_[k][l]);
      identity_ = identity_ && rotation_[k][l] == (k == l ? 1.0 : 0.0);
    }
  }
}

double BoxPairBound::LowerBound(const double* loA, const double* hiA, const double* loB, const double* hiB) const {
  double ca[3], ha[3], cb[3], hb[3], d[3];
  double magnitude = 0.0;
  for (int k = 0; k < 3; ++k) {
    ca[k] = 0.5 * (loA[k] + hiA[k]);
    ha[k] = 0.5 * (hiA[k] - loA[k]);
    hb[k] = 0.5 * (hiB[k] - loB[k]);
  }
  if (identity_) {
    // Both axis aligned in one frame: the exact box distance.
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double b = 0.5 * (loB[k] + hiB[k]) + translation_[k];
      const double gap = std::max({loA[k] - (b + hb[k]), 0.0, (b - hb[k]) - hiA[k]});
      d2 += gap * gap;
    }
    return std::sqrt(d2);
  }
  for (int k = 0; k < 3; ++k) {
    const double local = 0.5 * (loB[k] + hiB[k]);
    cb[k] = local;
  }
  for (int k = 0; k < 3; ++k) {
    double v = translation_[k];
    for (int l = 0; l < 3; ++l) v += rotation_[k][l] * cb[l];
    d[k] = v - ca[k];
    magnitude += std::abs(ca[k]) + std::abs(v) + ha[k] + hb[k];
  }
  // Along an orthonormal basis the gaps add in squares: every pair of
  // points differs by at least gap_k along each axis k, so by at least
  // sqrt(sum gap_k^2) (a box beside and above another is that far).
  const double slack = 16.0 * std::numeric_limits<double>::epsilon() * magnitude;
  double sumA = 0.0, sumB = 0.0;
  // A's axes.
  for (int k = 0; k < 3; ++k) {
    double rb = 0.0;
    for (int l = 0; l < 3; ++l) rb += absRotation_[k][l] * hb[l];
    const double g = std::max(0.0, std::abs(d[k]) - ha[k] - rb - slack);
    sumA += g * g;
  }
  // B's axes (the rotation's columns).
  for (int l = 0; l < 3; ++l) {
    double s = 0.0, ra = 0.0;
    for (int k = 0; k < 3; ++k) {
      s += rotation_[k][l] * d[k];
      ra += absRotation_[k][l] * ha[k];
    }
    const double g = std::max(0.0, std::abs(s) - ra - hb[l] - slack);
    sumB += g * g;
  }
  // (B's axes are orthonormal to rounding: a hair off the sum covers it.)
  double gap = std::max(std::sqrt(sumA), std::sqrt(sumB) * (1.0 - 1e-14));
  // The line through the centres.
  const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (length > 0.0) {
    double ra = 0.0, rb = 0.0;
    for (int k = 0; k < 3; ++k) ra += std::abs(d[k]) * ha[k];
    for (int l = 0; l < 3; ++l) {
      double s = 0.0;
      for (int k = 0; k < 3; ++k) s += rotation_[k][l] * d[k];
      rb += std::abs(s) * hb[l];
    }
    gap = std::max(gap, length - (ra + rb) / length - slack);
  }
  return std::max(0.0, gap);
}

OrientedBounds FitOrientedBounds(const PointMoments& moments, const double* origin, const double* xyz, int count) {
  OrientedBounds bounds;
  if (count <= 0) return bounds;
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  if (moments.count > 0.0 && moments.complete) {
    // Only the axes' quality depends on the eigenvectors; the extents below
    // hold whatever they are, so long as they are orthonormal.
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(moments.scatter);
    if (eigen.info() == Eigen::Success && eigen.eigenvectors().allFinite()) axes = eigen.eigenvectors();
  }
  double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                  std::numeric_limits<double>::infinity()};
  double hi[3] = {-lo[0], -lo[1], -lo[2]};
  double magnitude = 0.0;
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector3d x(xyz[3 * i] - origin[0], xyz[3 * i + 1] - origin[1], xyz[3 * i + 2] - origin[2]);
    magnitude = std::max(magnitude, x.cwiseAbs().maxCoeff());
    for (int a = 0; a < 3; ++a) {
      const double t = axes.col(a).dot(x);
      lo[a] = std::min(lo[a], t);
      hi[a] = std::max(hi[a], t);
    }
  }
  // Rounding of the projections, of the centre and of the lower bound's
  // use of the axes (which are orthonormal to a few ulps): ulps of the
  // points' magnitude about the origin and of the origin's.
  const double originMagnitude = std::max({std::abs(origin[0]), std::abs(origin[1]), std::abs(origin[2])});
  const double margin = 64.0 * std::numeric_limits<double>::epsilon() * (magnitude + originMagnitude);
  for (int a = 0; a < 3; ++a) {
    bounds.half[a] = 0.5 * (hi[a] - lo[a]) + margin;
    for (int k = 0; k < 3; ++k) bounds.axis[a][k] = axes(k, a);
  }
  for (int k = 0; k < 3; ++k) {
    double c = origin[k];
    for (int a = 0; a < 3; ++a) c += 0.5 * (lo[a] + hi[a]) * axes(k, a);
    bounds.center[k] = c;
  }
  return bounds;
}

void OrientedCorners(const OrientedBounds& box, double* corners) {
  for (int c = 0; c < 8; ++c) {
    for (int k = 0; k < 3; ++k) {
      double v = box.center[k];
      for (int i = 0; i < 3; ++i) v += ((c >> i) & 1 ? 1.0 : -1.0) * box.half[i] * box.axis[i][k];
      corners[3 * c + k] = v;
    }
  }
}

OrientedBounds Moved(const OrientedBounds& box, const kernels::RigidMotion& motion) {
  OrientedBounds moved;
  motion.Apply(box.center, moved.center);
  for (int j = 0; j < 3; ++j) {
    motion.Rotate(box.axis[j], moved.axis[j]);
    moved.half[j] = box.half[j];
  }
  return moved;
}

double OrientedPairLowerBound(const OrientedBounds& a, const OrientedBounds& b, const kernels::RigidMotion& bIntoA,
                              double target) {
  return OrientedPairLowerBound(a, Moved(b, bIntoA), target);
}

double OrientedPairLowerBound(const OrientedBounds& a, const OrientedBounds& b, double target) {
  // B's box in A's axes: centre offset t, B's axes as the columns of r
  // (r[i][j] = a_i . b_j).
  const double* center = b.center;
  const double(*axes)[3] = b.axis;
  double d[3], magnitude = 0.0;
  for (int k = 0; k < 3; ++k) {
    d[k] = center[k] - a.center[k];
    magnitude += std::abs(center[k]) + std::abs(a.center[k]) + a.half[k] + b.half[k];
  }
  const double slack = 64.0 * std::numeric_limits<double>::epsilon() * magnitude;
  target += slack;
  // The enclosing spheres: tight where the boxes lie side by side.
  const double ra2 = a.half[0] * a.half[0] + a.half[1] * a.half[1] + a.half[2] * a.half[2];
  const double rb2 = b.half[0] * b.half[0] + b.half[1] * b.half[1] + b.half[2] * b.half[2];
  const double centers = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  double gap = centers - std::sqrt(ra2) - std::sqrt(rb2);
  if (gap >= target) return gap - slack;
  double r[3][3], t[3], absR[3][3];
  for (int i = 0; i < 3; ++i) {
    t[i] = a.axis[i][0] * d[0] + a.axis[i][1] * d[1] + a.axis[i][2] * d[2];
    for (int j = 0; j < 3; ++j) {
      r[i][j] = a.axis[i][0] * axes[j][0] + a.axis[i][1] * axes[j][1] + a.axis[i][2] * axes[j][2];
      absR[i][j] = std::abs(r[i][j]);
    }
  }
  // A's axes, then B's: the thin boxes of flat patches facing each other.
  // Along either box's orthonormal axes the gaps add in squares (see
  // BoxPairBound); the axes are orthonormal to rounding, which the factor
  // a hair below 1 covers.
  constexpr double kBasis = 1.0 - 1e-14;
  double sum = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double rb = b.half[0] * absR[i][0] + b.half[1] * absR[i][1] + b.half[2] * absR[i][2];
    const double g = std::max(0.0, std::abs(t[i]) - a.half[i] - rb - slack);
    sum += g * g;
  }
  gap = std::max(gap, std::sqrt(sum) * kBasis);
  if (gap >= target) return gap - slack;
  sum = 0.0;
  for (int j = 0; j < 3; ++j) {
    const double ra = a.half[0] * absR[0][j] + a.half[1] * absR[1][j] + a.half[2] * absR[2][j];
    const double s = t[0] * r[0][j] + t[1] * r[1][j] + t[2] * r[2][j];
    const double g = std::max(0.0, std::abs(s) - ra - b.half[j] - slack);
    sum += g * g;
  }
  gap = std::max(gap, std::sqrt(sum) * kBasis);
  if (gap >= target) return gap - slack;
  // The 9 cross products a_i x b_j, of length sqrt(1 - r_ij^2).
  for (int i = 0; i < 3; ++i) {
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const double length2 = 1.0 - r[i][j] * r[i][j];
      if (!(length2 > 1e-12)) continue;
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double ra = a.half[i1] * absR[i2][j] + a.half[i2] * absR[i1][j];
      const double rb = b.half[j1] * absR[i][j2] + b.half[j2] * absR[i][j1];
      const double s = std::abs(t[i2] * r[i1][j] - t[i1] * r[i2][j]);
      gap = std::max(gap, (s - ra - rb) / std::sqrt(length2));
    }
  }
  return std::max(0.0, gap - slack);
}

kernels::RigidMotion RelativeMotion(const kernels::RigidMotion& motionA, const kernels::RigidMotion& motionB) {
  // A^-1 B: x -> Ra^T (Rb x + tb - ta).
  kernels::RigidMotion relative;
  for (int k = 0; k < 3; ++k) {
    double t = 0.0;
    for (int l = 0; l < 3; ++l) {
      double r = 0.0;
      for (int m = 0; m < 3; ++m) r += motionA.rotation[m][k] * motionB.rotation[m][l];
      relative.rotation[k][l] = r;
      t += motionA.rotation[l][k] * (motionB.translation[l] - motionA.translation[l]);
    }
    relative.translation[k] = t;
  }
  return relative;
}

}  // namespace invmap::engine
