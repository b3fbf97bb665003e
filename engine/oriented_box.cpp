#include "engine/oriented_box.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

namespace invmap::engine {
namespace {

constexpr float kInfF = std::numeric_limits<float>::infinity();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// The float axes' matrix is scaled to this norm: below 1 with room for the
/// rounding of the norm's own computation and of the scaled entries.
constexpr double kAxesNorm = 1.0 - 1.0 / (1 << 20);

/// Principal axes of a scatter matrix, as rows (any frame when it is
/// degenerate: the box stays valid whatever the axes, see the constructor).
/// In 2D the third row is 0. The closed-form solver: a tree's worth of them
/// is computed, and the iterative one was 11% of a mesh's build.
Eigen::Matrix3d PrincipalAxes(const Eigen::Matrix3d& scatter, int dimension) {
  Eigen::Matrix3d axes = Eigen::Matrix3d::Zero();
  if (dimension == 2) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver;
    solver.computeDirect(scatter.topLeftCorner<2, 2>());
    axes.topLeftCorner<2, 2>() = solver.eigenvectors().transpose();
  } else {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
    solver.computeDirect(scatter);
    axes = solver.eigenvectors().transpose();
  }
  return axes;
}

}  // namespace

OrientedBox UnboundedOrientedBox() {
  OrientedBox box;
  for (int j = 0; j < 3; ++j) {
    for (int k = 0; k < 3; ++k) box.axis[j][k] = 0.0f;
    box.lo[j] = -kInfF;
    box.hi[j] = kInfF;
  }
  return box;
}

PointMoments PointMoments::Of(const double* xyz, std::size_t count) {
  PointMoments m;
  m.count = static_cast<double>(count);
  m.complete = count > 0;
  if (count == 0) return m;
  for (std::size_t i = 0; i < count; ++i) m.mean += Eigen::Vector3d(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
  m.mean /= m.count;
  for (std::size_t i = 0; i < count; ++i) {
    const Eigen::Vector3d d = Eigen::Vector3d(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]) - m.mean;
    m.scatter += d * d.transpose();
  }
  return m;
}

PointMoments PointMoments::Merge(const PointMoments& a, const PointMoments& b) {
  PointMoments m;
  m.complete = a.complete && b.complete;
  m.count = a.count + b.count;
  if (m.count == 0.0) return m;
  const Eigen::Vector3d delta = b.mean - a.mean;
  m.mean = a.mean + delta * (b.count / m.count);
  m.scatter = a.scatter + b.scatter + delta * delta.transpose() * (a.count * b.count / m.count);
  return m;
}

OrientedBoxFitter::OrientedBoxFitter(int dimension, const double origin[3], const PointMoments& moments)
    : dimension_(dimension), origin_(origin[0], origin[1], origin[2]) {
  std::fill(lo_, lo_ + 3, kInf);
  std::fill(hi_, hi_ + 3, -kInf);
  if (!moments.complete || moments.count == 0.0 || !moments.scatter.allFinite()) {
    valid_ = false;
    return;
  }
  const Eigen::Matrix3d axes = PrincipalAxes(moments.scatter, dimension_);
  // Rounded to float, then scaled so that the float matrix's norm is below
  // 1: its square is at most the largest absolute row sum of R R^T (which
  // is about 1 + the axes' rounding and loss of orthogonality).
  Eigen::Matrix3d rounded;
  for (int j = 0; j < 3; ++j) {
    for (int k = 0; k < 3; ++k) rounded(j, k) = static_cast<double>(static_cast<float>(axes(j, k)));
  }
  const double norm2 = (rounded * rounded.transpose()).cwiseAbs().rowwise().sum().maxCoeff();
  if (!(norm2 > 0.0) || !std::isfinite(norm2)) {
    valid_ = false;
    return;
  }
  // Rounding the scaled entries again moves the norm by at most
  // 2^-24 * sqrt(3) (the Frobenius norm of the change), far within the
  // margin kAxesNorm leaves below 1.
  const double scale = kAxesNorm / std::sqrt(norm2);
  for (int j = 0; j < 3; ++j) {
    for (int k = 0; k < 3; ++k) axis_[j][k] = static_cast<float>(rounded(j, k) * scale);
  }
}

void OrientedBoxFitter::AddToInterval(const double* xyz, std::size_t count) {
  // The intervals with the float axes themselves, in double; Result()
  // widens them by the rounding of these sums. In locals: the members,
  // which `xyz` might alias for all the compiler knows, went to memory at
  // every point (the tree's fitting reads each point once per level).
  double axis[3][3], origin[3], lo[3], hi[3], magnitude = magnitude_;
  for (int j = 0; j < 3; ++j) {
    for (int k = 0; k < 3; ++k) axis[j][k] = static_cast<double>(axis_[j][k]);
    origin[j] = origin_[j];
    lo[j] = lo_[j];
    hi[j] = hi_[j];
  }
  for (std::size_t i = 0; i < count; ++i) {
    double offset[3], size = 0.0;
    for (int k = 0; k < 3; ++k) {
      offset[k] = xyz[3 * i + k] - origin[k];
      size += std::abs(offset[k]);
    }
    for (int j = 0; j < 3; ++j) {
      double t = 0.0;
      for (int k = 0; k < 3; ++k) t += axis[j][k] * offset[k];
      lo[j] = std::min(lo[j], t);
      hi[j] = std::max(hi[j], t);
    }
    magnitude = std::max(magnitude, size);
  }
  for (int j = 0; j < 3; ++j) {
    lo_[j] = lo[j];
    hi_[j] = hi[j];
  }
  magnitude_ = magnitude;
}

OrientedBox OrientedBoxFitter::Result() const {
  if (!valid_ || !std::isfinite(magnitude_)) return UnboundedOrientedBox();
  for (int j = 0; j < 3; ++j) {
    if (!std::isfinite(lo_[j]) || !std::isfinite(hi_[j])) return UnboundedOrientedBox();
  }
  // A few units of 2^-53 of the offsets bound the sums' rounding; this is
  // far more. Then outward to float.
  const double margin = magnitude_ * 0x1.0p-48;
  OrientedBox box;
  for (int j = 0; j < 3; ++j) {
    std::copy(axis_[j], axis_[j] + 3, box.axis[j]);
    box.lo[j] = std::nextafter(static_cast<float>(lo_[j] - margin), -kInfF);
    box.hi[j] = std::nextafter(static_cast<float>(hi_[j] + margin), kInfF);
  }
  if (dimension_ == 2) {
    // The zero third axis: every point sits at 0 on it, which bounds nothing.
    box.lo[2] = -kInfF;
    box.hi[2] = kInfF;
  }
  return box;
}

}  // namespace invmap::engine
