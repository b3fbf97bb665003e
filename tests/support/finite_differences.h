// Derivatives by central differences, for tests that check analytic bounds
// against the function itself.
#pragma once

#include <Eigen/Dense>

namespace invmap::testing {

/// Hessian of f (a callable on const double* with `dims` <= 3 coordinates)
/// at t, by central differences with step h.
template <class F>
Eigen::MatrixXd FiniteDifferenceHessian(const F& f, int dims, const double* t, double h) {
  Eigen::MatrixXd hessian(dims, dims);
  for (int a = 0; a < dims; ++a) {
    for (int b = a; b < dims; ++b) {
      double sum = 0.0;
      for (const int sa : {-1, 1}) {
        for (const int sb : {-1, 1}) {
          double x[3] = {t[0], dims > 1 ? t[1] : 0.0, dims > 2 ? t[2] : 0.0};
          x[a] += sa * h;
          x[b] += sb * h;
          sum += sa * sb * f(x);
        }
      }
      hessian(a, b) = hessian(b, a) = sum / (4 * h * h);
    }
  }
  return hessian;
}

/// Smallest eigenvalue of a symmetric matrix.
inline double SmallestEigenvalue(const Eigen::MatrixXd& m) {
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(m).eigenvalues().minCoeff();
}

}  // namespace invmap::testing
