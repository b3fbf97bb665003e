#include "engine/analytic_start.h"

#include "kernels/own_parameter.h"

namespace invmap::engine {

bool PredictOnElementarySurface(const CellStore& store, const WarmStart& warm, const double* p, std::int64_t* cell,
                                double* ref) {
  const kernels::AnalyticCell* analytic = store.analytic(warm.cell);
  if (!analytic) return false;
  double own[2];
  kernels::SurfaceFoot(*analytic, p, own);
  int across[3] = {0, 0, 0};
  bool leaves = false;
  for (int d = 0; d < 2; ++d) {
    const double lo = analytic->paramLo[d], hi = lo + analytic->paramScale[d];
    across[d] = own[d] < lo ? -1 : own[d] > hi ? 1 : 0;
    leaves = leaves || across[d] != 0;
  }
  std::int64_t to = warm.cell;
  if (leaves) {
    const std::int64_t next = store.SplineNeighbor(warm.cell, across);
    if (next >= 0 && !store.inRegion(next)) to = next;
  }
  // Reference coordinates in the cell reached: the arc's own map inside
  // its span, a linear one beyond it (only the side matters there).
  const CellOrigin& origin = store.origin(to);
  for (int d = 0; d < 2; ++d) {
    const double lo = origin.paramLo[d], scale = origin.paramScale[d];
    const bool inside = own[d] >= lo && own[d] <= lo + scale;
    ref[d] = inside ? kernels::ReferenceOfOwn(lo, scale, (origin.angular >> d) & 1, own[d]) : (own[d] - lo) / scale;
  }
  ref[2] = 0.0;
  *cell = to;
  return true;
}

}  // namespace invmap::engine
