// Bernstein basis of one simplex factor with first and second derivatives.
#pragma once

#include "kernels/cell_shape.h"

namespace invmap::kernels {

/// How many derivatives to compute.
enum class JetOrder { Value = 0, First = 1, Second = 2 };

/// Values and derivatives of every Bernstein polynomial of one simplex factor
/// of dimension Dim at one point, with respect to the factor's free
/// coordinates (s1..sDim; the implicit barycentric coordinate is
/// 1 - s1 - .. - sDim). Sized for degree kMaxDegree; only the first `size`
/// entries of the requested orders are set, so the unused tail costs nothing.
template <int Dim>
struct FactorBasis {
  static constexpr int kCapacity = SimplexBasisSize(Dim, kMaxDegree);
  /// Second derivatives are stored as the lower triangle, (i, j) with j <= i
  /// at i * (i + 1) / 2 + j.
  static constexpr int kSecondCount = Dim * (Dim + 1) / 2;

  int size = 0;                        ///< Number of polynomials.
  double value[kCapacity];             ///< B_k(s).
  double d1[kCapacity][Dim];           ///< dB_k/ds_i.
  double d2[kCapacity][kSecondCount];  ///< d2B_k/ds_i ds_j, lower triangle.
};

/// Evaluates the Bernstein basis of a simplex factor of dimension Dim (1, 2
/// or 3) and degree `degree` at free coordinates `s` (Dim values). Points
/// outside the simplex are allowed (the polynomials extend). Entries beyond
/// the requested order are left unset.
template <int Dim>
void EvaluateFactorBasis(int degree, const double* s, JetOrder order, FactorBasis<Dim>* out);

}  // namespace invmap::kernels
