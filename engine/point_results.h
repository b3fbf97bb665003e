// Writing the answers of a batch: each point's answer into the results in
// Morton order, and those results back to the points' input order.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "engine/cell_store.h"
#include "engine/point_search.h"
#include "engine/warm_start.h"
#include "invmap/invmap.h"
#include "kernels/active_set.h"
#include "kernels/tolerances.h"

namespace invmap::engine {

/// Sizes every array of `results` for `count` points.
void ResizeResults(std::int64_t count, Results* results);

/// Point `i` of `results` gets `status` (None or Invalid) and no answer.
void WriteNotFound(Status status, std::int64_t i, Results* results);

/// Writes one point's answer at position `index` of `results` (its place in
/// the chunk's Morton order) and keeps it as the next point's warm start.
/// (Defined below, so that the bucket loop inlines it as it did when they
/// shared a file; see the note in engine/point_search.h.)
void WriteFound(const CellStore& store, const PointSearch& search, std::int64_t index, WarmStart* warm,
                Results* results);

/// Answers [begin, end) of `source` written to answers to[begin..end) of
/// *target. One array at a time: each answer lands on cache lines of its
/// own in every array, and a loop over all seven arrays at once kept that
/// many streams of misses open (the whole scatter 1.25x slower, measured on
/// a million random points).
void ScatterResults(const Results& source, const std::int64_t* to, std::int64_t begin, std::int64_t end,
                    Results* target);

inline void WriteFound(const CellStore& store, const PointSearch& search, std::int64_t index, WarmStart* warm,
                       Results* results) {
  if (search.bestCell < 0) {
    WriteNotFound(Status::None, index, results);
    results->iterations[index] = search.iterations;
    return;
  }
  const int dim = store.dimension();
  const CellOrigin origin = store.origin(search.bestCell);
  const kernels::CellSolveResult& r = search.bestResult;
  const int pd = kernels::CellShape::ParamDimOf(origin.type);
  // Exactly in the reference domain: the solves leave a coordinate or a
  // simplex's sum an ulp outside it now and then.
  double ref[3] = {r.ref[0], r.ref[1], r.ref[2]};
  kernels::SnapToDomain(origin.type, ref);
  // A cell as wide as the space (a volume, or a surface in the plane) that
  // holds the point, to the distance tolerance of its size: the point is
  // its own closest point, at distance 0 (the map at the solved parameters
  // would be an ulp or a Newton residual off it).
  const bool holds =
      search.inside ||
      (pd == dim && r.distance <= kernels::kDistanceTolerance * store.cellSize(search.bestCell));
  results->status[index] = Status::Found;
  results->patch[index] = origin.patch;
  results->cell[index] = origin.indexInPatch;
  store.ReportedParameters(search.bestCell, ref, &results->params[3 * index]);
  for (int k = 0; k < 3; ++k) results->closest[3 * index + k] = k < dim ? (holds ? search.p[k] : r.closest[k]) : 0.0;
  // Beyond about 1e154 the solvers' squared distances overflow: measure
  // such an answer's distance from its closest point instead.
  results->distance[index] =
      holds ? 0.0
      : std::isfinite(r.distance)
          ? r.distance
          : std::hypot(r.closest[0] - search.p[0], r.closest[1] - search.p[1], r.closest[2] - search.p[2]);
  results->iterations[index] = search.iterations;
  warm->cell = search.bestCell;
  for (int k = 0; k < 3; ++k) {
    warm->point[k] = search.p[k];
    warm->ref[k] = r.ref[k];
    warm->closest[k] = r.closest[k];
  }
  warm->model.known = search.bestModel >= 0;
  if (warm->model.known) warm->model = search.scratch.models[search.bestModel];
}

}  // namespace invmap::engine
