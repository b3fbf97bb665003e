// 3 x 3 linear systems by Cramer's rule: for the tiny, well-separated cases
// (a tetrahedron's barycentric coordinates, a volume's Newton step) where a
// pivoting factorization costs more than it gains.
#pragma once

namespace invmap::kernels {

/// Determinant of the 3 x 3 matrix with columns a, b, c.
inline double Determinant3(const double* a, const double* b, const double* c) {
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
}

/// x with x0 a + x1 b + x2 c = rhs, given det = Determinant3(a, b, c),
/// which the caller has checked to be nonzero.
inline void CramerSolve3(const double* a, const double* b, const double* c, double det, const double* rhs,
                         double* x) {
  x[0] = Determinant3(rhs, b, c) / det;
  x[1] = Determinant3(a, rhs, c) / det;
  x[2] = Determinant3(a, b, rhs) / det;
}

}  // namespace invmap::kernels
