#include "kernels/local_solver.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/active_set.h"
#include "kernels/jet_cache.h"
#include "kernels/kkt_point.h"
#include "kernels/line_factor_newton.h"
#include "kernels/line_search.h"
#include "kernels/stationarity.h"
#include "kernels/step_selection.h"
#include "kernels/tangent_plane.h"
#include "kernels/tolerances.h"

namespace invmap::kernels {
namespace {

using Vector = Eigen::Vector3d;

/// The Hessian of half the squared distance from `point`, J^T J + sum_k r_k
/// d2x_k with r = x - point, from a second-order jet.
void DistanceHessian(const MapJet& jet, const double* point, int pd, int ad, double (*hessian)[3]) {
  for (int i = 0; i < pd; ++i) {
    for (int j = 0; j < pd; ++j) {
      double h = 0.0;
      for (int k = 0; k < ad; ++k) h += jet.d1[k][i] * jet.d1[k][j] + (jet.x[k] - point[k]) * jet.d2[k][i][j];
      hessian[i][j] = h;
    }
  }
}

/// Releases the enforced constraints of a start on the boundary that the
/// descent direction there points away from (negative multiplier):
/// otherwise the solve would first converge along their face, and only then
/// release them. `jet`: the map at the start, to first order at least.
void ReleaseInwardConstraints(const CellView& cell, const MapJet& jet, const double* point, ActiveSet* active) {
  const CellShape& shape = cell.shape;
  double grad[3] = {0, 0, 0};
  for (int i = 0; i < shape.paramDim(); ++i) {
    for (int k = 0; k < cell.ambientDim; ++k) grad[i] += jet.d1[k][i] * (jet.x[k] - point[k]);
  }
  const ActiveSet start = *active;
  for (int f = 0; f < shape.numFactors(); ++f) {
    for (int k = 0; k <= shape.factor(f).dim; ++k) {
      if ((start.enforced[f] & (1u << k)) && ReleaseDerivative(shape, start, f, k, grad) < 0.0) {
        active->enforced[f] &= ~(1u << k);
      }
    }
  }
}

}  // namespace

LocalSolveResult LocalSolve(const CellView& cell, const double* point, const double* startRef,
                            const LocalSolveOptions& options) {
  const CellShape& shape = cell.shape;
  const int pd = shape.paramDim();
  const int ad = cell.ambientDim;
  const bool fullRank = pd == ad;
  const double size = options.size;
  const JetOrder order = options.affine ? JetOrder::First : JetOrder::Second;

  LocalSolveResult result;
  double ref[3] = {0, 0, 0};
  std::copy(startRef, startRef + pd, ref);
  ClampToDomain(shape, ref);
  ActiveSet active = ActiveSetAt(shape, ref);
  SnapToFace(shape, active, ref);

  int releases = 0;
  bool fullRankAllowed = true;
  int releasedFactor = -1, releasedIndex = -1;  // the constraint released last
  JetCache jets;
  bool exclusionPending = options.confirmExclusion && options.exclusionLevel > -std::numeric_limits<double>::infinity();
  // A start on the boundary (a neighbour's edge, a control point there)
  // keeps only the constraints the descent direction presses against.
  // (Volumes keep theirs: their starts are inset, see NearestControlPointStart.)
  if (!fullRank && (active.enforced[0] != 0 || active.enforced[1] != 0 || active.enforced[2] != 0)) {
    jets.EnsureAt(cell, ref, order);
    ReleaseInwardConstraints(cell, *jets.atRef, point, &active);
  }
  int iter = 0;
  const FastOutcome fast =
      LineFactorNewtonFor(cell, point, options, active, ref, &jets, &exclusionPending, &iter, &result);
  result.converged = fast == FastOutcome::Converged;
  result.aboveLevel = fast == FastOutcome::AboveLevel;
  for (; fast == FastOutcome::Handover && iter < options.maxIterations; ++iter) {
    result.iterations = iter + 1;
    // 7.3.2.1 only while no constraint has been met: a point that drove the
    // solve onto the boundary is outside the cell, where -J^-1 r keeps
    // pointing back out (and near a collapsed edge, cycles with releases).
    const bool noneEnforced = active.enforced[0] == 0 && active.enforced[1] == 0 && active.enforced[2] == 0;
    fullRankAllowed = fullRankAllowed && noneEnforced;
    const bool useFullRank = fullRank && fullRankAllowed;
    const JetOrder need = useFullRank ? JetOrder::First : order;
    jets.EnsureAt(cell, ref, need);
    const MapJet& jet = *jets.atRef;
    double r[3] = {0, 0, 0};
    double f = 0.0;
    for (int k = 0; k < ad; ++k) {
      r[k] = jet.x[k] - point[k];
      f += r[k] * r[k];
    }
    if (exclusionPending && TangentPlaneLowerBound(shape, ad, jet, point, ref, options.exclusionLevel, size) > 0.0) {
      exclusionPending = false;
      if (options.confirmExclusion(options.exclusionContext)) {
        result.aboveLevel = true;
        break;
      }
    }
    // On the boundary and still far from the point: it most likely lies
    // outside the cell. (Giving up on a point inside only costs the caller a
    // full solve.)
    if (options.stopAtBoundary && !noneEnforced && f > kBoundaryGiveUp * kBoundaryGiveUp * size * size) break;
    double grad[3] = {0, 0, 0};  // gradient of f / 2 = J^T r
    for (int i = 0; i < pd; ++i) {
      for (int k = 0; k < ad; ++k) grad[i] += jet.d1[k][i] * r[k];
    }
    const DirectionScale scale{jet, ad, pd, kGradientTolerance * (size + std::sqrt(f)), kThinDirection * size};
    const double fNoise = RoundingOfF(point, r, ad, size, f);
    const StepLimits limits = StepLimitsAt(jet, pd, ad, size);

    const Vector g = Eigen::Map<const Vector>(grad);
    // The common cases without the fallbacks' set-up: in the interior, the
    // step -J^-1 r of a volume cell (7.3.2.1) or the Newton step of the full
    // Hessian; on a face of a cell of line factors, the Newton step over the
    // free parameters. Both are the reduced step below (whose basis is then
    // square, or picks the free parameters). Anything else falls through.
    int freeCoords[3] = {0, 1, 2};
    int freeCount = 0;
    bool freeStationary = true;
    // A cell of line factors is judged along its free parameters (-1: not one).
    int lineCoords[3];
    const int lineCount = FreeLineParameters(shape, active, lineCoords);
    if (releasedFactor < 0 && noneEnforced && useFullRank) {
      // J spans every direction: stationary where r itself is as small as
      // each direction's test asks (a J too singular for the step below
      // leaves the decision to the general path's test).
      freeCount = pd;
      freeStationary = std::sqrt(f) <= scale.perLength;
    } else if (releasedFactor < 0 && noneEnforced && order == JetOrder::Second) {
      freeCount = pd;
      if (lineCount >= 0) {
        freeStationary = FreeParametersStationary(lineCoords, lineCount, grad, scale);
      } else {
        FaceBasis whole;
        BuildFaceBasis(shape, active, &whole);
        freeStationary = IsStationaryOnFace(whole, grad, scale);
      }
    } else if (releasedFactor < 0 && !noneEnforced && order == JetOrder::Second && lineCount >= 0) {
      freeCount = lineCount;
      std::copy(lineCoords, lineCoords + lineCount, freeCoords);
      freeStationary = FreeParametersStationary(freeCoords, freeCount, grad, scale);
    }
    bool finalOnFace = false;
    if (freeCount > 0 && !freeStationary) {
      double step[3];
      if (useFullRank ? FullRankStep(jet, r, pd, size, step)
                      : NewtonStepOver(jet, r, grad, freeCoords, freeCount, ad, step)) {
        const StepOutcome outcome =
            LineSearch(cell, point, active, f, fNoise, limits, g, Eigen::Map<const Vector>(step), true, need,
                       jets.trial, ref);
        if (outcome == StepOutcome::Moved) {
          jets.AcceptTrial(need, ref);
          continue;
        }
        if (outcome == StepOutcome::Blocked) {
          SnapToFace(shape, active, ref);
          jets.valid = false;
          continue;
        }
        if (outcome == StepOutcome::Final) {
          jets.valid = false;
          if (noneEnforced) {
            result.converged = true;
            break;
          }
          // On a face, stationary there: the enforced constraints'
          // multipliers decide below, as after the general path's final step.
          finalOnFace = true;
        }
      }
    }
    if (!finalOnFace) {
      FaceBasis face;
      BuildFaceBasis(shape, active, &face);
      // The common paths' test above already judged this face (the same
      // iterate and active set) when it found it stationary.
      const bool stationary = face.columns == 0 || (freeCount > 0 && freeStationary) ||
                              (lineCount >= 0 ? FreeParametersStationary(lineCoords, lineCount, grad, scale)
                                              : IsStationaryOnFace(face, grad, scale));
      if (!stationary) {
        FaceSteps steps = StepsOnFace(jet, r, grad, pd, ad, face, order, useFullRank, size);
        if (releasedFactor >= 0 && MovesOut(shape, releasedFactor, releasedIndex, steps.model.data())) {
          // Right after a release the multiplier promises descent into the
          // interior; a curved model's step back out would only cycle.
          steps.model = steps.descent;
          steps.newton = false;
        }
        releasedFactor = -1;

        // The model's step first, then plain descent: a step that the line
        // search cannot use (a nearly singular model) falls back to the gradient.
        const Vector candidates[2] = {steps.model, steps.descent};
        bool moved = false, final = false;
        for (int c = 0; c < 2 && !moved && !final; ++c) {
          const StepOutcome outcome = LineSearch(cell, point, active, f, fNoise, limits, g, candidates[c],
                                                 steps.newton && c == 0, need, jets.trial, ref);
          if (outcome == StepOutcome::Rejected || outcome == StepOutcome::Negligible) continue;
          if (outcome == StepOutcome::Moved) {
            jets.AcceptTrial(need, ref);
          } else {
            if (outcome == StepOutcome::Blocked) SnapToFace(shape, active, ref);
            jets.valid = false;
          }
          final = outcome == StepOutcome::Final;
          moved = !final;
        }
        // Otherwise no decrease is possible (or the step was negligible): a
        // stationary point up to rounding, as below.
        if (moved) continue;
      }
    }

    // Stationary on the current face: release the constraint whose
    // multiplier is most negative, if any (algorithm 5, lines 33-45): among
    // those below minus their own tolerance, the steepest per unit of
    // mapped length (DirectionScale).
    int releaseFactor = -1, releaseIndex = -1;
    double steepest = 0.0;
    for (int fac = 0; fac < shape.numFactors(); ++fac) {
      for (int k = 0; k <= shape.factor(fac).dim; ++k) {
        if (!(active.enforced[fac] & (1u << k))) continue;
        double direction[3];
        ReleaseDirection(shape, active, fac, k, direction);
        const double mu = direction[0] * grad[0] + direction[1] * grad[1] + direction[2] * grad[2];
        const double length = std::max(scale.MappedLength(direction), scale.floorLength);
        if (!(mu < -scale.Tolerance(length)) || !(mu / length < steepest)) continue;
        steepest = mu / length;
        releaseFactor = fac;
        releaseIndex = k;
      }
    }
    if (releaseFactor >= 0 && releases < 4 * (pd + 1)) {
      active.enforced[releaseFactor] &= ~(1u << releaseIndex);
      releasedFactor = releaseFactor;
      releasedIndex = releaseIndex;
      ++releases;
      continue;
    }
    result.converged = true;
    break;
  }

  std::copy(ref, ref + pd, result.ref);
  // The last second-order jet, when it lies within a final step of the
  // answer (kFinalStep: far closer than any use of the Hessian needs), gives
  // the Hessian there without another evaluation.
  AnswerModel* model = options.checkKkt ? options.model : nullptr;
  if (model) {
    bool jetNearAnswer = jets.order == JetOrder::Second;
    for (int i = 0; i < pd; ++i) jetNearAnswer = jetNearAnswer && std::abs(jets.at[i] - ref[i]) <= kFinalStep;
    if (jetNearAnswer) {
      DistanceHessian(*jets.atRef, point, pd, ad, model->hessian);
    } else {
      std::fill(&model->hessian[0][0], &model->hessian[0][0] + 9, 0.0);
    }
  }
  const JetOrder finalOrder = options.checkKkt ? JetOrder::First : JetOrder::Value;
  jets.EnsureAt(cell, ref, finalOrder);
  result.kkt = options.checkKkt && result.converged && IsKktPoint(cell, *jets.atRef, point, ref, size);
  std::copy(jets.atRef->x, jets.atRef->x + ad, result.closest);
  if (model) {
    std::copy(&jets.atRef->d1[0][0], &jets.atRef->d1[0][0] + 9, &model->jacobian[0][0]);
    model->known = true;
  } else if (options.model) {
    options.model->known = false;
  }
  result.squaredDistance = SquaredDistance(*jets.atRef, point, ad);
  result.onBoundary = active.enforced[0] != 0 || active.enforced[1] != 0 || active.enforced[2] != 0;
  return result;
}

}  // namespace invmap::kernels
