// The line search of the local solve (algorithm 5): Armijo backtracking along
// the feasible part of a step, with the step lengths and the decrease below
// which no move can be told from rounding.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "kernels/active_set.h"
#include "kernels/cell_map.h"
#include "kernels/tolerances.h"

namespace invmap::kernels {

/// |x - point|^2 for the mapped point x of `jet` (ambientDim coordinates).
inline double SquaredDistance(const MapJet& jet, const double* point, int ambientDim) {
  double f = 0.0;
  for (int k = 0; k < ambientDim; ++k) f += (jet.x[k] - point[k]) * (jet.x[k] - point[k]);
  return f;
}

/// The rounding level of f = |r|^2 (r = x - point): the map's coordinates
/// carry errors of a few ulps of the coordinates' magnitude, and f doubles
/// their relative size.
inline double RoundingOfF(const double* point, const double* r, int ambientDim, double size, double f) {
  double magnitude = size;
  for (int k = 0; k < ambientDim; ++k) magnitude = std::max(magnitude, std::abs(point[k]) + std::abs(r[k]));
  const double rError = kMapRounding * magnitude;
  return 2.0 * std::sqrt(f) * rError + rError * rError;
}

/// The step lengths below which a move is negligible (kStepTolerance) and
/// an unchecked Newton step is final (kFinalStep), at an iterate whose map
/// has the jet `jet`. Both are meant for a map that moves about `size` per
/// unit of reference coordinate; where it moves faster (|J| above size: a
/// rational cell with weights many orders of magnitude apart crosses a
/// whole control leg in 1e-15 of its parameter) they shrink in proportion,
/// so that the mapped point still moves less than they allow.
struct StepLimits {
  double negligible = kStepTolerance;
  double final = kFinalStep;
};
inline StepLimits StepLimitsAt(const MapJet& jet, int pd, int ad, double size) {
  double jac2 = 0.0;
  for (int k = 0; k < ad; ++k) {
    for (int i = 0; i < pd; ++i) jac2 += jet.d1[k][i] * jet.d1[k][i];
  }
  StepLimits limits;
  if (jac2 > size * size) {
    const double shrink = size / std::sqrt(jac2);
    limits.negligible *= shrink;
    limits.final *= shrink;
  }
  return limits;
}

enum class StepOutcome { Moved, Blocked, Negligible, Rejected, Final };

/// Armijo backtracking along the feasible part of `step`. On success moves
/// `ref` (and enforces the blocking constraint when the whole feasible step
/// was taken); Negligible when the accepted move is below limits.negligible or
/// the decrease it promises is below `fNoise`, the rounding level of f (no
/// evaluation could then tell a decrease from rounding). A short Newton step
/// (`newton`, within the domain, at most limits.final) that promises only such
/// a decrease is in the quadratic convergence region: it is taken unchecked,
/// and the outcome is Final. (A long step promising so little means a nearly
/// singular Hessian, where the model cannot be trusted.)
/// Trial points are evaluated to `trialOrder` into *trialJet, so after Moved
/// it holds the map at the new `ref` for the next iteration.
StepOutcome LineSearch(const CellView& cell, const double* point, ActiveSet& active, double f, double fNoise,
                       const StepLimits& limits, const Eigen::Vector3d& g, const Eigen::Vector3d& step, bool newton,
                       JetOrder trialOrder, MapJet* trialJet, double* ref);

}  // namespace invmap::kernels
