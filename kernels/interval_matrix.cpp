#include "kernels/interval_matrix.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "kernels/tolerances.h"

namespace invmap::kernels {
namespace {

bool IntervalTest(int dim, const double lo[3][3], const double hi[3][3]) {
  Eigen::Matrix3d mid = Eigen::Matrix3d::Zero();
  double radius2 = 0.0;
  for (int a = 0; a < dim; ++a) {
    for (int b = a; b < dim; ++b) {
      const double m = 0.5 * (lo[a][b] + hi[a][b]);
      const double r = 0.5 * (hi[a][b] - lo[a][b]);
      mid(a, b) = mid(b, a) = m;
      radius2 += (a == b ? 1.0 : 2.0) * r * r;
    }
  }
  double lambdaMin;
  if (dim == 2) {
    // From the eigenvalues' half-difference, not the determinant: a product
    // of two large entries would overflow (inf - inf), a square here only to
    // +infinity, which rejects.
    const double halfDifference = 0.5 * (mid(0, 0) - mid(1, 1));
    lambdaMin = 0.5 * (mid(0, 0) + mid(1, 1)) - std::sqrt(halfDifference * halfDifference + mid(0, 1) * mid(0, 1));
  } else {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
    eigen.computeDirect(mid, Eigen::EigenvaluesOnly);
    lambdaMin = eigen.eigenvalues()(0);
  }
  // The margin keeps the test away from the rounding of its own arithmetic.
  const double scale = mid.cwiseAbs().maxCoeff();
  return lambdaMin > std::sqrt(radius2) + kPositivityMargin * scale;
}

bool ScaledTest(int dim, const double lo[3][3], const double hi[3][3]) {
  // H = D^1/2 N D^1/2 with D the diagonal of H, so N has a unit diagonal
  // and |N_ab| <= beta_ab = max |H_ab| / sqrt(min H_aa min H_bb).
  // lambda_min(N) >= 1 - rho(|N - I|) >= 1 - rho(beta), so rho(beta) < 1
  // proves every H positive definite.
  Eigen::Matrix3d beta = Eigen::Matrix3d::Zero();
  for (int a = 0; a < dim; ++a) {
    for (int b = a + 1; b < dim; ++b) {
      const double largest = std::max(std::abs(lo[a][b]), std::abs(hi[a][b]));
      // Square roots apart: the product of two large diagonals overflows.
      beta(a, b) = beta(b, a) = largest / (std::sqrt(lo[a][a]) * std::sqrt(lo[b][b]));
    }
  }
  double rho;
  if (dim == 2) {
    rho = beta(0, 1);
  } else {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
    eigen.computeDirect(beta, Eigen::EigenvaluesOnly);
    rho = eigen.eigenvalues()(2);
  }
  // The margin keeps the test away from the rounding of its own arithmetic.
  return rho < 1.0 - kPositivityMargin;
}

}  // namespace

bool IntervalMatrixIsPositive(int dim, const double lo[3][3], const double hi[3][3]) {
  for (int a = 0; a < dim; ++a) {
    if (!(lo[a][a] > 0.0)) return false;
  }
  if (dim == 1) return true;
  return IntervalTest(dim, lo, hi) || ScaledTest(dim, lo, hi);
}

}  // namespace invmap::kernels
