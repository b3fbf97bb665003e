// The buckets of one chunk of a batch, in parallel: each bucket's culling
// (algorithm 3), then each of its points' search (algorithm 4), its answer
// written in Morton order.
#pragma once

#include "engine/query_points.h"
#include "engine/search_index.h"
#include "invmap/invmap.h"

namespace invmap::engine {

/// Inverts `points` (a run of the Morton order that starts a bucket), in
/// parallel over its buckets of `bucketSize` points; answer s of `sorted` is
/// that of point s.
void InvertBuckets(const SearchIndex& index, const QueryPoints& points, int bucketSize, const InversionOptions& options,
                   Results* sorted);

}  // namespace invmap::engine
