#include "engine/simplex_lanes.h"

#include "engine/bucket_candidates.h"
#include "engine/point_search.h"

namespace invmap::engine {

bool SolveAffineSimplexLanes(const CellStore& store, const QueryPoints& points, std::int64_t first, std::int64_t count,
                             double maxDistance, BucketScratch& scratch) {
  bool any = false;
  for (const CellCandidate& candidate : scratch.candidates) any = any || SolvedAsLanes(store, candidate.cell);
  if (!any) return false;
  const int dim = store.dimension();
  const int lanes = static_cast<int>(count);
  for (int k = 0; k < 3; ++k) {
    scratch.laneCoord[k].resize(lanes);
    scratch.laneRef[k].resize(lanes);
    scratch.laneClosest[k].resize(lanes);
  }
  scratch.laneDistance.resize(lanes);
  scratch.laneStatus.resize(lanes);
  scratch.laneBestCell.assign(lanes, -1);
  scratch.laneBest.resize(lanes);
  for (int l = 0; l < lanes; ++l)
    for (int k = 0; k < 3; ++k) scratch.laneCoord[k][l] = k < dim ? points.coord[k][first + l] : 0.0;
  kernels::QueryLane query;
  query.count = lanes;
  kernels::ResultLane result;
  for (int k = 0; k < 3; ++k) {
    query.coord[k] = scratch.laneCoord[k].data();
    result.ref[k] = scratch.laneRef[k].data();
    result.closest[k] = scratch.laneClosest[k].data();
  }
  result.distance = scratch.laneDistance.data();
  result.status = scratch.laneStatus.data();
  for (const CellCandidate& candidate : scratch.candidates) {
    if (!SolvedAsLanes(store, candidate.cell)) continue;
    const std::int64_t cell = store.subdivisionCell(candidate.cell);
    // The vertices from the store: a mesh triangle has no solver to ask.
    const int pd = store.shape(cell).paramDim();
    const double* vertices[4];
    for (int v = 0; v <= pd; ++v) vertices[v] = store.SimplexVertex(cell, v);
    kernels::CellSolver::SolveAffineSimplexLane(pd, store.dimension(), vertices, query, result);
    for (int l = 0; l < lanes; ++l) {
      if (scratch.laneStatus[l] == kernels::PointStatus::InvalidInput) continue;
      const double d = scratch.laneDistance[l];
      // As PointSearch::Beats: the gap tolerance admits equality and the
      // cell's band beyond it, a found answer only a strictly better one (so
      // ties keep the earlier candidate).
      const bool beats = scratch.laneBestCell[l] >= 0
                             ? d < scratch.laneBest[l].distance
                             : d <= maxDistance || d <= maxDistance + PointSearch::GapBand(store.cellSize(cell));
      if (!beats) continue;
      kernels::CellSolveResult& best = scratch.laneBest[l];
      for (int k = 0; k < 3; ++k) {
        best.ref[k] = scratch.laneRef[k][l];
        best.closest[k] = scratch.laneClosest[k][l];
      }
      best.distance = d;
      best.status = scratch.laneStatus[l];
      best.iterations = 0;
      scratch.laneBestCell[l] = cell;
    }
  }
  return true;
}

}  // namespace invmap::engine
