#include "kernels/curvature_bounds.h"

#include <algorithm>
#include <cmath>

#include "kernels/interval_matrix.h"
#include "kernels/tolerances.h"

namespace invmap::kernels {

CurvatureBounds::CurvatureBounds(const DistanceNets& nets, const HessianStencil& stencil)
    : paramDim_(nets.shape().paramDim()), ambientDim_(nets.ambientDim()), rational_(nets.rational()) {
  for (int k = 0; k < ambientDim_; ++k) center_[k] = nets.center()[k];
  // The nets' coefficients carry rounding of the products that made them:
  // each range is widened well beyond it.
  const auto store = [&](const double* net, Range* ranges) {
    double lo[3][3], hi[3][3];
    stencil.HessianRanges(net, lo, hi);
    for (int a = 0; a < paramDim_; ++a) {
      for (int b = a; b < paramDim_; ++b) {
        const double widen = kNetRangeWidening * std::max(std::abs(lo[a][b]), std::abs(hi[a][b]));
        ranges[Entry(a, b)] = Range{lo[a][b] - widen, hi[a][b] + widen};
      }
    }
  };
  store(nets.nn(), nn_);
  Range nw[3][kEntries];
  for (int k = 0; k < ambientDim_; ++k) store(nets.nw(k), nw[k]);
  for (int e = 0; e < kEntries; ++e) {
    for (int k = 0; k < ambientDim_; ++k) nw_[e][k] = nw[k][e];
  }
  if (rational_) store(nets.ww(), ww_);
}

bool CurvatureBounds::ProvesConvex(const double* point, double level) const {
  double d[3] = {0, 0, 0}, distance2 = 0.0;
  for (int k = 0; k < ambientDim_; ++k) {
    d[k] = point[k] - center_[k];
    distance2 += d[k] * d[k];
  }
  const double weightFactor = distance2 - level;
  double lo[3][3] = {}, hi[3][3] = {};
  for (int a = 0; a < paramDim_; ++a) {
    for (int b = a; b < paramDim_; ++b) {
      const int e = Entry(a, b);
      // -2 d . H(NW): its midpoint, and how far the ranges let it move.
      double along = 0.0, spread = 0.0, size = 0.0;
      for (int k = 0; k < ambientDim_; ++k) {
        along += d[k] * nw_[e][k].mid();
        spread += std::abs(d[k]) * nw_[e][k].radius();
        size += std::abs(d[k] * nw_[e][k].mid());
      }
      double weightLo = 0.0, weightHi = 0.0;
      if (rational_) {
        weightLo = std::min(weightFactor * ww_[e].lo, weightFactor * ww_[e].hi);
        weightHi = std::max(weightFactor * ww_[e].lo, weightFactor * ww_[e].hi);
        size += std::abs(weightLo) + std::abs(weightHi);
      }
      // The rounding of the sums above, far below the ranges' widening.
      const double rounding = kBoundSumRounding * size;
      lo[a][b] = nn_[e].lo - 2.0 * (along + spread) + weightLo - rounding;
      hi[a][b] = nn_[e].hi - 2.0 * (along - spread) + weightHi + rounding;
    }
  }
  return IntervalMatrixIsPositive(paramDim_, lo, hi);
}

}  // namespace invmap::kernels
