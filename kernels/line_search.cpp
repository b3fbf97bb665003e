#include "kernels/line_search.h"

namespace invmap::kernels {

StepOutcome LineSearch(const CellView& cell, const double* point, ActiveSet& active, double f, double fNoise,
                       const StepLimits& limits, const Eigen::Vector3d& g, const Eigen::Vector3d& step, bool newton,
                       JetOrder trialOrder, MapJet* trialJet, double* ref) {
  const CellShape& shape = cell.shape;
  const int pd = shape.paramDim();
  int blockFactor = -1, blockIndex = -1;
  const double feasible = FeasibleFraction(shape, active, ref, step.data(), &blockFactor, &blockIndex);
  const double slope = 2.0 * g.dot(step);  // derivative of |r|^2 along the step
  if (!(slope < 0.0)) return StepOutcome::Rejected;
  const double length = step.norm();
  if (blockFactor >= 0 && feasible * length <= limits.negligible) {
    // Already on that constraint's face (up to rounding): a descent step
    // that leaves the domain at once means the constraint becomes active.
    active.enforced[blockFactor] |= 1u << blockIndex;
    return StepOutcome::Blocked;
  }
  if (newton && blockFactor < 0 && -slope <= fNoise && length <= limits.final) {
    for (int i = 0; i < pd; ++i) ref[i] += step[i];
    return StepOutcome::Final;
  }
  double alpha = feasible;
  double trial[3];
  for (int halving = 0; halving < 60; ++halving) {
    if (alpha * length <= limits.negligible || -alpha * slope <= fNoise) return StepOutcome::Negligible;
    for (int i = 0; i < pd; ++i) trial[i] = ref[i] + alpha * step[i];
    EvaluateMap(cell, trial, trialOrder, trialJet);
    const double fTrial = SquaredDistance(*trialJet, point, cell.ambientDim);
    if (fTrial <= f + kSufficientDecrease * alpha * slope && fTrial < f) {
      std::copy(trial, trial + pd, ref);
      if (blockFactor >= 0 && alpha == feasible) {
        active.enforced[blockFactor] |= 1u << blockIndex;
        return StepOutcome::Blocked;
      }
      return StepOutcome::Moved;
    }
    alpha *= 0.5;
  }
  return StepOutcome::Rejected;
}

}  // namespace invmap::kernels
