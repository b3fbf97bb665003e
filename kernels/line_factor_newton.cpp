#include "kernels/line_factor_newton.h"

#include <algorithm>
#include <cmath>

#include "kernels/line_search.h"
#include "kernels/stationarity.h"
#include "kernels/step_selection.h"
#include "kernels/tangent_plane.h"
#include "kernels/tolerances.h"

namespace invmap::kernels {
namespace {

/// The iterations of a curve or surface cell of line factors (lines and
/// quads in a higher-dimensional space) in their common case: Newton steps
/// of the full Hessian over the free parameters (those of no enforced
/// constraint: on a face, the others stay at 0 or 1) that stay in the domain
/// and pass the Armijo test at once, until the face is stationary and no
/// enforced constraint's multiplier asks for a release. The steps, tests and
/// tolerances are the general loop's (see LocalSolve); what is left out is
/// its active-set machinery, and the dimensions are fixed at compile time.
/// That machinery's generic loops took about twice the time of the map's
/// evaluation on a near point of a bicubic surface (measured). Any other
/// case (a step that leaves the domain or fails the Armijo test, a Hessian
/// that is not positive definite, a constraint to release) hands over to the
/// general loop at the current iterate, with the active set unchanged.
template <int PD, int AD>
FastOutcome LineFactorNewton(const CellView& cell, const double* point, const LocalSolveOptions& options,
                             const ActiveSet& active, double* ref, JetCache* jets, bool* exclusionPending, int* iter,
                             LocalSolveResult* result) {
  const double size = options.size;
  // Parameter i is factor i's: free, or held at 0 (constraint 1 enforced,
  // released toward +u_i) or at 1 (constraint 0, released toward -u_i).
  int freeCoords[3], m = 0;
  double releaseSign[3] = {0, 0, 0};
  for (int i = 0; i < PD; ++i) {
    if (active.enforced[i] == 0) {
      freeCoords[m++] = i;
    } else {
      releaseSign[i] = (active.enforced[i] & 2u) ? 1.0 : -1.0;
    }
  }
  // True when no enforced constraint's multiplier is below minus its tolerance.
  const auto noRelease = [&](const double* grad, const double* tolerance) {
    for (int i = 0; i < PD; ++i) {
      if (releaseSign[i] != 0.0 && releaseSign[i] * grad[i] < -tolerance[i]) return false;
    }
    return true;
  };
  for (; *iter < options.maxIterations; ++*iter) {
    result->iterations = *iter + 1;
    jets->EnsureAt(cell, ref, JetOrder::Second);
    const MapJet& jet = *jets->atRef;
    double r[AD], f = 0.0;
    for (int k = 0; k < AD; ++k) {
      r[k] = jet.x[k] - point[k];
      f += r[k] * r[k];
    }
    if (*exclusionPending &&
        TangentPlaneLowerBound(cell.shape, AD, jet, point, ref, options.exclusionLevel, size) > 0.0) {
      *exclusionPending = false;
      if (options.confirmExclusion(options.exclusionContext)) return FastOutcome::AboveLevel;
    }
    double grad[3] = {0, 0, 0};
    for (int i = 0; i < PD; ++i) {
      for (int k = 0; k < AD; ++k) grad[i] += jet.d1[k][i] * r[k];
    }
    // Each parameter's slope against its own tolerance (DirectionScale).
    const DirectionScale scale{jet, AD, PD, kGradientTolerance * (size + std::sqrt(f)), kThinDirection * size};
    double tolerance[3];
    bool stationary = true;
    for (int i = 0; i < PD; ++i) tolerance[i] = scale.Tolerance(scale.ColumnLength(i));
    for (int a = 0; a < m; ++a) stationary = stationary && std::abs(grad[freeCoords[a]]) <= tolerance[freeCoords[a]];
    if (stationary) return noRelease(grad, tolerance) ? FastOutcome::Converged : FastOutcome::Handover;
    const double fNoise = RoundingOfF(point, r, AD, size, f);

    double step[3];
    if (!NewtonStepOver(jet, r, grad, freeCoords, m, AD, step)) return FastOutcome::Handover;
    double trial[3] = {ref[0], ref[1], ref[2]}, slope = 0.0, length2 = 0.0;
    bool inside = true;
    for (int a = 0; a < m; ++a) {
      const int i = freeCoords[a];
      trial[i] = ref[i] + step[i];
      inside = inside && trial[i] >= 0.0 && trial[i] <= 1.0;
      slope += 2.0 * grad[i] * step[i];
      length2 += step[i] * step[i];
    }
    const double length = std::sqrt(length2);
    if (!inside) return FastOutcome::Handover;
    const StepLimits limits = StepLimitsAt(jet, PD, AD, size);
    if (-slope <= fNoise && length <= limits.final) {
      // In the quadratic region: the step is taken unchecked, and on a face
      // the multipliers of this iterate decide (as in the general loop).
      std::copy(trial, trial + PD, ref);
      jets->valid = false;
      return noRelease(grad, tolerance) ? FastOutcome::Converged : FastOutcome::Handover;
    }
    if (length <= limits.negligible || -slope <= fNoise) return FastOutcome::Handover;
    EvaluateMap(cell, trial, JetOrder::Second, jets->trial);
    const double fTrial = SquaredDistance(*jets->trial, point, AD);
    if (!(fTrial <= f + kSufficientDecrease * slope && fTrial < f)) return FastOutcome::Handover;
    std::copy(trial, trial + PD, ref);
    jets->AcceptTrial(JetOrder::Second, ref);
  }
  return FastOutcome::Handover;
}

}  // namespace

FastOutcome LineFactorNewtonFor(const CellView& cell, const double* point, const LocalSolveOptions& options,
                                const ActiveSet& active, double* ref, JetCache* jets, bool* exclusionPending,
                                int* iter, LocalSolveResult* result) {
  const CellShape& shape = cell.shape;
  if (options.affine || !shape.isBox()) return FastOutcome::Handover;
  const int pd = shape.paramDim();
  if (pd == 2 && cell.ambientDim == 3) {
    return LineFactorNewton<2, 3>(cell, point, options, active, ref, jets, exclusionPending, iter, result);
  }
  if (pd == 1 && cell.ambientDim == 2) {
    return LineFactorNewton<1, 2>(cell, point, options, active, ref, jets, exclusionPending, iter, result);
  }
  if (pd == 1 && cell.ambientDim == 3) {
    return LineFactorNewton<1, 3>(cell, point, options, active, ref, jets, exclusionPending, iter, result);
  }
  return FastOutcome::Handover;
}

}  // namespace invmap::kernels
