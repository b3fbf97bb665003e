// The points of a bucket solved together, as lanes, on the affine simplices
// among its candidates (docs/how-it-works.md, "Solve per point").
#pragma once

#include <cstdint>

#include "engine/bucket_scratch.h"
#include "engine/cell_store.h"
#include "engine/query_points.h"

namespace invmap::engine {

/// The bucket's points [first, first + count) of `points` that target an
/// affine segment, triangle or tetrahedron among scratch.candidates are
/// solved together, one candidate cell at a time for all lanes, by the
/// vectorized closed form; each lane keeps its best (scratch.laneBestCell,
/// scratch.laneBest). Returns false (nothing done) when no candidate is one.
bool SolveAffineSimplexLanes(const CellStore& store, const QueryPoints& points, std::int64_t first, std::int64_t count,
                             double maxDistance, BucketScratch& scratch);

}  // namespace invmap::engine
