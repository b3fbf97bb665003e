// Bernstein basis of one simplex factor with first and second derivatives.
#pragma once

#include "kernels/cell_shape.h"

namespace invmap::kernels {

/// Largest basis of one factor that a map (not a net) can have: a degree
/// kMaxDegree tetrahedron.
constexpr int kMaxFactorBasis = SimplexBasisSize(3, kMaxDegree);

/// Values and derivatives of every Bernstein polynomial of one simplex factor
/// at one point, with respect to the factor's free coordinates (s1..sd; the
/// implicit barycentric coordinate is 1 - s1 - .. - sd).
struct FactorBasis {
  int size = 0;                            ///< Number of polynomials.
  double value[kMaxFactorBasis];           ///< B_k(s).
  double d1[kMaxFactorBasis][3];           ///< dB_k/ds_i.
  double d2[kMaxFactorBasis][3][3];        ///< d2B_k/ds_i ds_j (symmetric).
};

/// How many derivatives to compute.
enum class JetOrder { Value = 0, First = 1, Second = 2 };

/// Evaluates the Bernstein basis of a simplex factor of dimension `dim` and
/// degree `degree` at free coordinates `s` (dim values). Points outside the
/// simplex are allowed (the polynomials extend). Entries beyond the requested
/// order are left unset.
void EvaluateFactorBasis(int dim, int degree, const double* s, JetOrder order, FactorBasis* out);

}  // namespace invmap::kernels
