// Constraints of a reference domain (a tensor product of simplices) and the
// orthogonal barycentric basis of the face they leave free (section 7.3.1.1).
#pragma once

#include "kernels/cell_shape.h"
#include "kernels/tolerances.h"

namespace invmap::kernels {

/// Which barycentric constraints lambda_k >= 0 are enforced (held at zero),
/// one bit mask per factor (bit k for lambda_k; lambda_0 = 1 - sum of the
/// factor's free coordinates). At least one coordinate of every factor stays
/// free. The "inactive indices" of algorithm 5.
struct ActiveSet {
  unsigned enforced[kMaxFactors] = {0, 0, 0};
};

/// Barycentric coordinates (lambda_0..lambda_d) of factor `f` at reference
/// point `ref`. Inline: the local solve's every step asks for them.
inline void FactorBarycentric(const CellShape& shape, int f, const double* ref, double* lambda) {
  const SimplexFactor& fac = shape.factor(f);
  lambda[0] = 1.0;
  for (int i = 0; i < fac.dim; ++i) {
    lambda[i + 1] = ref[fac.offset + i];
    lambda[0] -= ref[fac.offset + i];
  }
}

/// The enforced constraints of a point: barycentric coordinates at zero (at
/// most kOnFaceTolerance).
inline ActiveSet ActiveSetAt(const CellShape& shape, const double* ref) {
  ActiveSet active;
  for (int f = 0; f < shape.numFactors(); ++f) {
    double lambda[4];
    FactorBarycentric(shape, f, ref, lambda);
    const int dim = shape.factor(f).dim;
    for (int k = 0; k <= dim; ++k) {
      if (lambda[k] <= kOnFaceTolerance) active.enforced[f] |= 1u << k;
    }
    // Keep one coordinate free (a vertex leaves exactly one).
    if (active.enforced[f] == (1u << (dim + 1)) - 1) active.enforced[f] &= ~1u;
  }
  return active;
}

/// Puts `ref` exactly on the face of every enforced constraint (rounding in
/// the steps would otherwise leave it a hair off).
void SnapToFace(const CellShape& shape, const ActiveSet& active, double* ref);

/// True when `step` decreases barycentric coordinate k of factor f.
inline bool MovesOut(const CellShape& shape, int f, int k, const double* step) {
  const SimplexFactor& fac = shape.factor(f);
  double d = 0.0;
  if (k > 0) {
    d = step[fac.offset + k - 1];
  } else {
    for (int i = 0; i < fac.dim; ++i) d -= step[fac.offset + i];
  }
  return d < 0.0;
}

/// Largest step fraction in (0, 1] that keeps every free barycentric
/// coordinate non-negative, and the constraint that blocks it (factor, index).
inline double FeasibleFraction(const CellShape& shape, const ActiveSet& active, const double* ref, const double* step,
                               int* blockFactor, int* blockIndex) {
  double alpha = 1.0;
  *blockFactor = -1;
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& fac = shape.factor(f);
    double lambda[4], dLambda[4];
    FactorBarycentric(shape, f, ref, lambda);
    dLambda[0] = 0.0;
    for (int i = 0; i < fac.dim; ++i) {
      dLambda[i + 1] = step[fac.offset + i];
      dLambda[0] -= step[fac.offset + i];
    }
    for (int k = 0; k <= fac.dim; ++k) {
      if ((active.enforced[f] & (1u << k)) || dLambda[k] >= 0.0) continue;
      // Most constraints are nowhere near blocking: those with twice the
      // room the step needs skip the division (the test is exact: their
      // fraction is at least 2 alpha, rounding included).
      const double room = std::max(0.0, lambda[k]);
      if (room >= 2.0 * alpha * -dLambda[k]) continue;
      const double a = room / -dLambda[k];
      if (a < alpha) {
        alpha = a;
        *blockFactor = f;
        *blockIndex = k;
      }
    }
  }
  return alpha;
}

/// Clamps `ref` into the reference domain (each simplex factor separately).
void ClampToDomain(const CellShape& shape, double* ref);

/// Moves `ref`, a point of the reference domain up to rounding, into it
/// exactly: no coordinate below 0 or above 1, and each simplex factor's sum
/// at most 1 in exact arithmetic (its largest coordinates lowered by an ulp
/// at a time; ClampToDomain's rounded sum can be 1 while the exact one is
/// 1 + 1e-16). For reported parameters, which users check against the domain.
void SnapToDomain(CellType type, double* ref);

/// The orthogonal basis of the tangent space of the face left free by
/// `active`, written in the cell's parameter coordinates: column c maps a
/// reduced step to a parameter step. Per factor, the free barycentric indices
/// k_0 < .. < k_{r-1} give the Helmert vectors
///   v_t = (e_{k_0} + .. + e_{k_{t-1}} - t e_{k_t}) / sqrt(t (t + 1)),  t = 1..r-1,
/// orthonormal in barycentric space and orthogonal to (1, .., 1), so the
/// reduced residual's norm is the norm of the projected gradient whatever
/// the active set (the continuity of 7.3.1.1). Tensor products pad each
/// factor's vectors with zeros (7.3.1.2).
struct FaceBasis {
  int columns = 0;          ///< Dimension of the face.
  double t[3][3] = {};      ///< t[i][c]: parameter i of column c.
};

/// Builds the FaceBasis of `active`.
void BuildFaceBasis(const CellShape& shape, const ActiveSet& active, FaceBasis* basis);

/// The parameter step that releases constraint k of factor f: e_k - e_{k0}
/// in barycentric space, k0 the factor's first free index, written in the
/// cell's parameters (3 values, zero outside the factor).
void ReleaseDirection(const CellShape& shape, const ActiveSet& active, int f, int k, double* step);

/// Directional derivative of a function with parameter gradient `grad` along
/// ReleaseDirection. A negative value is the Lagrange multiplier saying the
/// constraint should be released.
double ReleaseDerivative(const CellShape& shape, const ActiveSet& active, int f, int k, const double* grad);

}  // namespace invmap::kernels
