// The certificate that closes a subdomain of the pair search around a KKT
// point: a proof that g = Q - f(x_S) WW (kernels/pair_nets.h) stays above
// -allowed on the whole subdomain S, from the KKT conditions at x_S and
// bounds of g's Hessian over S.
//
// Taylor's theorem with the Hessian's bounds gives, for every x in S
// (D = x - x_S, in S's local coordinates, scaled so the Hessian's diagonal
// is about one),
//   g(x) >= grad g(x_S) . D + D^T H D / 2,   H within the bounds,
// and at a KKT point grad g(x_S) = sum mu_c n_c + e with mu_c >= 0 on the
// constraints holding there (n_c . D >= 0 inside the domain) and e the
// negligible residual. Split D into N, its part along the active normals,
// and F, along the free face: the multipliers give at least
// mu_min sigma |D_N| (sigma the normals' least singular value), the
// Hessian's bounds at least lambda_F |D_F|^2 - 2 b |D_N| |D_F| - c |D_N|^2
// (lambda_F the least eigenvalue over the face's block, b the mixed
// block's norm, c the normal block's). The bound is concave in |D_N| and
// checked at its ends over S. It covers at once:
//  - an interior minimum where g is convex (lambda_F >= 0: g >= 0);
//  - a minimum on the domain's boundary where g is not convex but grows
//    away from the face faster than it bends (the point solves' face
//    certificate, for any factor type);
//  - a valley of equal distances (parallel cylinders: lambda_F rounding
//    below zero), closed within the search's tolerance, which no strict
//    convexity test can close.
#pragma once

#include "kernels/pair_problem.h"

namespace invmap::kernels {

struct PairCertificateInput {
  int n = 0;  ///< Joint parameters.
  /// Bounds of g's Hessian over S (n x n, row-major) in coordinates y with
  /// local coordinates t = x_S + basis y (`basis` n x n, column c at
  /// basis[c n]; null: the identity, the bounds are in t).
  const double* lo = nullptr;
  const double* hi = nullptr;
  const double* basis = nullptr;
  /// x_S in S's local coordinates.
  double point[kMaxPairParams] = {};
  /// S's vertices in its local coordinates, n values each.
  int numVertices = 0;
  const double* vertices = nullptr;
  /// The constraints holding at x_S: their normals (local coordinates) and
  /// the multipliers of g along them.
  int numActive = 0;
  double normal[kMaxPairConstraints][kMaxPairParams] = {};
  double multiplier[kMaxPairConstraints] = {};
  /// grad g(x_S) - sum multiplier normal (local coordinates).
  double residual[kMaxPairParams] = {};
  /// g >= -allowed over S is what the search needs.
  double allowed = 0.0;
};

/// True when g >= -allowed is proved over the whole of S.
bool ProvesPairBound(const PairCertificateInput& input);

/// True when every symmetric n x n matrix within the bounds (row-major) is
/// positive definite (its diagonal scaled to one, Weyl's bound).
bool IntervalPositiveDefinite(int n, const double* lo, const double* hi);

}  // namespace invmap::kernels
