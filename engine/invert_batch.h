// The batched inversion of many points (algorithm 4 per point, algorithm 3
// per bucket of spatially close points), dispatched over TBB tasks.
#pragma once


#include "engine/query_points.h"
#include "engine/search_index.h"
#include "invmap/invmap.h"

namespace invmap::engine {

/// Inverts every point of `points` onto the cells of `index`, then its
/// partition-of-unity surfaces, and writes the results at the points' input
/// indices.
/// Results are identical for any thread count: the buckets are fixed runs of
/// the Morton order, and each point's answer depends only on its bucket.
/// `results` is resized to points.count (sized only: every field of every
/// point is written).
void InvertBatch(const SearchIndex& index, const QueryPoints& points, const InversionOptions& options,
                 Results* results);

}  // namespace invmap::engine
