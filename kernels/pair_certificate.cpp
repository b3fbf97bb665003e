#include "kernels/pair_certificate.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace invmap::kernels {
namespace {

using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxPairParams, kMaxPairParams>;
using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxPairParams, 1>;
/// S's vertices: a product of simplices of at most 6 dimensions has at most 2^6.
using VertexMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxPairParams, 64>;

/// The spectral norm of every E with |E_ab| <= rad_ab is at most that of
/// rad (a nonnegative matrix: its largest singular value).
double SpreadNorm(const Matrix& rad) {
  if (rad.rows() == 0 || rad.cols() == 0) return 0.0;
  Eigen::JacobiSVD<Matrix> svd(rad);
  return svd.singularValues()(0);
}

/// Least eigenvalue of every symmetric matrix mid + E with |E_ab| <= rad_ab
/// (Weyl: lambda_min(mid) - ||rad||_2); +inf for an empty block.
double LeastEigenvalue(const Matrix& mid, const Matrix& rad) {
  if (mid.rows() == 0) return std::numeric_limits<double>::infinity();
  Eigen::SelfAdjointEigenSolver<Matrix> eigen(mid, Eigen::EigenvaluesOnly);
  return eigen.eigenvalues()(0) - SpreadNorm(rad);
}

/// Largest norm of every matrix mid + E with |E_ab| <= rad_ab; 0 when empty.
double LargestNorm(const Matrix& mid, const Matrix& rad) {
  if (mid.rows() == 0 || mid.cols() == 0) return 0.0;
  Eigen::JacobiSVD<Matrix> svd(mid);
  return svd.singularValues()(0) + SpreadNorm(rad);
}

/// The bound of the file comment with the constraints `pressing` (a subset
/// of the active ones with positive multipliers) spanning N; the others'
/// terms, mu_c n_c . D, are dropped (they are at least 0) or, for negative
/// multipliers, join the residual.
/// The input in the coordinates y of the Hessian's bounds: normals and
/// residual as covectors, S's vertices as offsets from x_S.
struct Transformed {
  Matrix normals;  ///< n x numActive
  Vector residual;
  VertexMatrix offsets;  ///< n x numVertices
};

bool ProvesWith(const PairCertificateInput& in, const Transformed& data, const Matrix& midIn, const Matrix& radIn,
                const Vector& scale, const bool* pressing) {
  const int n = in.n;
  Vector residual = data.residual;
  Matrix normals(n, in.numActive);
  int used = 0;
  double leastMultiplier = std::numeric_limits<double>::infinity();
  for (int c = 0; c < in.numActive; ++c) {
    const Vector normal = data.normals.col(c);
    if (pressing[c]) {
      normals.col(used++) = scale.asDiagonal() * normal;
      leastMultiplier = std::min(leastMultiplier, in.multiplier[c]);
    } else if (in.multiplier[c] < 0.0) {
      residual += in.multiplier[c] * normal;
    }
  }
  normals.conservativeResize(n, used);
  residual = scale.asDiagonal() * residual;
  const double residualNorm = residual.norm();

  // Orthonormal bases: N spans the pressing normals, F the rest.
  Matrix basis = Matrix::Identity(n, n);
  double sigma = 0.0;
  if (used > 0) {
    Eigen::HouseholderQR<Matrix> qr(normals);
    basis = qr.householderQ() * Matrix::Identity(n, n);
    Eigen::JacobiSVD<Matrix> svd(normals);
    sigma = svd.singularValues()(used - 1);
    if (!(sigma > 0.0)) return false;
  }
  const int free = n - used;
  const Matrix rotated = basis.transpose() * midIn * basis;
  const Matrix spread = basis.cwiseAbs().transpose() * radIn * basis.cwiseAbs();
  const double lambdaF = LeastEigenvalue(rotated.bottomRightCorner(free, free), spread.bottomRightCorner(free, free));
  const double mixed = LargestNorm(rotated.topRightCorner(used, free), spread.topRightCorner(used, free));
  const double normalBend =
      std::max(0.0, -LeastEigenvalue(rotated.topLeftCorner(used, used), spread.topLeftCorner(used, used)));

  // The extent of S around x_S along N and F (convex in the vertex, so the
  // largest at a vertex of S).
  double reachN = 0.0, reachF = 0.0;
  for (int v = 0; v < in.numVertices; ++v) {
    Vector d(n);
    for (int a = 0; a < n; ++a) d[a] = data.offsets(a, v) / scale[a];
    const Vector along = basis.transpose() * d;
    reachN = std::max(reachN, along.head(used).norm());
    reachF = std::max(reachF, along.tail(free).norm());
  }
  const double push = used > 0 ? leastMultiplier * sigma : 0.0;
  // The lower bound at |D_N| = s, least over |D_F| = r in [0, reachF]. The
  // residual pulls along F as the mixed block does: where g bends up along
  // F, the least of lambda_F r^2 / 2 - pull r is -pull^2 / (2 lambda_F),
  // not -pull reachF (a residual of rounding times the face's whole length
  // would exceed the tolerance of a distance of 1e-6 of the cells' size).
  auto bound = [&](double s) {
    const double pull = mixed * s + residualNorm;
    double faceTerm;
    if (free == 0) {
      faceTerm = 0.0;
    } else if (lambdaF > 0.0) {
      const double r = std::min(pull / lambdaF, reachF);
      faceTerm = 0.5 * lambdaF * r * r - pull * r;
    } else {
      faceTerm = std::min(0.0, 0.5 * lambdaF * reachF * reachF - pull * reachF);
    }
    return push * s - 0.5 * normalBend * s * s + faceTerm - residualNorm * s;
  };
  return bound(0.0) >= -in.allowed && bound(reachN) >= -in.allowed;
}

/// The bound with every coordinate scaled by S's extent along it (|y_a| <=
/// e_a over S): D^T H D >= lambda_min(E H E) |y / e|^2 >= n lambda_min when
/// that is negative. Where S is long in a direction g does not bend along
/// (a valley of equal distances), the isotropic bound multiplies the other
/// directions' slight negative bend by that length; this one does not.
bool ProvesByExtents(const PairCertificateInput& in, const Transformed& data, const Matrix& mid, const Matrix& rad) {
  const int n = in.n;
  Vector extent = Vector::Zero(n);
  for (int v = 0; v < in.numVertices; ++v) {
    for (int a = 0; a < n; ++a) extent[a] = std::max(extent[a], std::abs(data.offsets(a, v)));
  }
  const Matrix scaledMid = extent.asDiagonal() * mid * extent.asDiagonal();
  const Matrix scaledRad = extent.asDiagonal() * rad * extent.asDiagonal();
  const double lambda = LeastEigenvalue(scaledMid, scaledRad);
  // Pressing constraints only add mu n . D >= 0; the others join the residual.
  Vector residual = data.residual;
  for (int c = 0; c < in.numActive; ++c) {
    if (in.multiplier[c] < 0.0) residual += in.multiplier[c] * data.normals.col(c);
  }
  const double linear = residual.cwiseAbs().dot(extent);
  const double bound = 0.5 * std::min(0.0, lambda) * n - linear;
  return bound >= -in.allowed;
}

}  // namespace

bool IntervalPositiveDefinite(int n, const double* lo, const double* hi) {
  Matrix mid(n, n), rad(n, n);
  for (int a = 0; a < n; ++a) {
    if (!(lo[a * n + a] > 0.0)) return false;
    for (int b = 0; b < n; ++b) {
      if (!std::isfinite(lo[a * n + b]) || !std::isfinite(hi[a * n + b])) return false;
      mid(a, b) = 0.5 * (lo[a * n + b] + hi[a * n + b]);
      rad(a, b) = 0.5 * (hi[a * n + b] - lo[a * n + b]);
    }
  }
  Vector scale(n);
  for (int a = 0; a < n; ++a) scale[a] = 1.0 / std::sqrt(mid(a, a));
  mid = scale.asDiagonal() * mid * scale.asDiagonal();
  rad = scale.asDiagonal() * rad * scale.asDiagonal();
  return LeastEigenvalue(mid, rad) > 1e-12;
}

bool ProvesPairBound(const PairCertificateInput& in) {
  const int n = in.n;
  Matrix mid(n, n), rad(n, n);
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) {
      const double l = in.lo[a * n + b], h = in.hi[a * n + b];
      if (!std::isfinite(l) || !std::isfinite(h)) return false;
      mid(a, b) = 0.5 * (l + h);
      rad(a, b) = 0.5 * (h - l);
    }
  }
  // Scale the coordinates so the Hessian's diagonal is about one: a cell
  // 1e3 times the other's size must not lend the other its scale.
  double largestDiagonal = 0.0;
  for (int a = 0; a < n; ++a) largestDiagonal = std::max(largestDiagonal, std::abs(mid(a, a)));
  if (!(largestDiagonal > 0.0)) largestDiagonal = 1.0;
  Vector scale(n);  // D^(-1/2): local = scale * scaled
  // By the diagonal's magnitude: where g bends down (a minimum on a face,
  // held by its multiplier) the floor made that direction 1e6 times longer
  // than the others, and its bend swamped what the multiplier proves.
  for (int a = 0; a < n; ++a) scale[a] = 1.0 / std::sqrt(std::max(std::abs(mid(a, a)), 1e-12 * largestDiagonal));
  mid = scale.asDiagonal() * mid * scale.asDiagonal();
  rad = scale.asDiagonal() * rad * scale.asDiagonal();

  // N spanned by every constraint with a positive multiplier, or by none:
  // a multiplier near zero pushes too little to pay for the directions it
  // takes out of the face (a minimum on an edge two cells share).
  bool pressing[kMaxPairConstraints];
  bool any = false;
  for (int c = 0; c < in.numActive; ++c) {
    pressing[c] = in.multiplier[c] > 0.0;
    any = any || pressing[c];
  }
  // Into the coordinates y of the bounds: t - x_S = M y.
  Matrix m = Matrix::Identity(n, n);
  if (in.basis) {
    for (int c = 0; c < n; ++c) {
      for (int a = 0; a < n; ++a) m(a, c) = in.basis[c * n + a];
    }
  }
  Transformed data;
  data.normals.resize(n, in.numActive);
  for (int c = 0; c < in.numActive; ++c) {
    Vector normal(n);
    for (int a = 0; a < n; ++a) normal[a] = in.normal[c][a];
    data.normals.col(c) = m.transpose() * normal;
  }
  data.residual.resize(n);
  for (int a = 0; a < n; ++a) data.residual[a] = in.residual[a];
  data.residual = m.transpose() * data.residual;
  VertexMatrix offsets(n, in.numVertices);
  for (int v = 0; v < in.numVertices; ++v) {
    for (int a = 0; a < n; ++a) offsets(a, v) = in.vertices[v * n + a] - in.point[a];
  }
  data.offsets = in.basis ? VertexMatrix(m.partialPivLu().solve(offsets)) : offsets;
  if (any && ProvesWith(in, data, mid, rad, scale, pressing)) return true;
  std::fill(pressing, pressing + kMaxPairConstraints, false);
  return ProvesWith(in, data, mid, rad, scale, pressing) || ProvesByExtents(in, data, mid, rad);
}

}  // namespace invmap::kernels
