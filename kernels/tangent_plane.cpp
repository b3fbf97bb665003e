#include "kernels/tangent_plane.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/tolerances.h"

namespace invmap::kernels {

double TangentPlaneLowerBound(const CellShape& shape, int ambientDim, const MapJet& jet, const double* point,
                              const double* ref, double level, double size) {
  double r[3] = {0, 0, 0}, f = 0.0;
  for (int k = 0; k < ambientDim; ++k) {
    r[k] = jet.x[k] - point[k];
    f += r[k] * r[k];
  }
  const double excess = f - level;
  if (!(excess > 0.0)) return -std::numeric_limits<double>::infinity();  // also NaN
  // grad g / W^2 = grad f + 2 (grad W / W) (f - level); W = 1 and grad W = 0
  // for a polynomial cell.
  double slope[3] = {0, 0, 0};
  for (int i = 0; i < shape.paramDim(); ++i) {
    for (int k = 0; k < ambientDim; ++k) slope[i] += 2.0 * jet.d1[k][i] * r[k];
    slope[i] += 2.0 * jet.logWeightSlope[i] * excess;
  }
  // A linear function's least value over a simplex is at a vertex: per
  // factor, its origin or one of its unit points.
  double least = excess;
  for (int fac = 0; fac < shape.numFactors(); ++fac) {
    const SimplexFactor& factor = shape.factor(fac);
    double lowestVertex = 0.0;
    for (int i = factor.offset; i < factor.offset + factor.dim; ++i) {
      least -= slope[i] * ref[i];
      lowestVertex = std::min(lowestVertex, slope[i]);
    }
    least += lowestVertex;
  }
  if (!(least > 0.0)) return -std::numeric_limits<double>::infinity();
  // The residual carries rounding of the coordinates' magnitude (as in the
  // local solve's noise level): its effect on f and on the slopes over the
  // unit domain, where each reference coordinate moves by at most one.
  double magnitude = size, columns = 0.0, weightSlope = 0.0;
  for (int k = 0; k < ambientDim; ++k) magnitude = std::max({magnitude, std::abs(point[k]), std::abs(jet.x[k]) + size});
  for (int i = 0; i < shape.paramDim(); ++i) {
    for (int k = 0; k < ambientDim; ++k) columns += std::abs(jet.d1[k][i]);
    weightSlope += 2.0 * std::abs(jet.logWeightSlope[i]);
  }
  const double delta = kMapRounding * magnitude;
  const double rounding = (2.0 * delta * (std::sqrt(f) + columns) + delta * delta) * (1.0 + weightSlope);
  const double bound = least - rounding;
  return std::isfinite(bound) ? bound : -std::numeric_limits<double>::infinity();
}

}  // namespace invmap::kernels
