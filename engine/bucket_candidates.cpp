#include "engine/bucket_candidates.h"

#include "engine/nearest_cells.h"
#include "engine/point_search.h"
#include "engine/simplex_lanes.h"

namespace invmap::engine {
namespace {

/// Fills scratch.searched and scratch.searchedBox from the bucket's candidates.
void GatherSearchedCandidates(const CellStore& store, bool lanesSolved, BucketScratch& scratch) {
  scratch.searched.clear();
  for (int c = 0; c < static_cast<int>(scratch.candidates.size()); ++c) {
    if (!(lanesSolved && SolvedAsLanes(store, scratch.candidates[c].cell))) scratch.searched.push_back(c);
  }
  const std::size_t n = scratch.searched.size();
  for (std::vector<double>& axis : scratch.searchedBox) axis.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    const std::int64_t s = scratch.candidates[scratch.searched[j]].cell;
    double lo[3], hi[3];
    store.SubdivisionBox(s, lo, hi);
    for (int k = 0; k < store.dimension(); ++k) {
      scratch.searchedBox[k][j] = lo[k];
      scratch.searchedBox[3 + k][j] = hi[k];
    }
  }
}

}  // namespace

BucketList CullBucket(const CellStore& store, const Bvh& bvh, const QueryPoints& points, std::int64_t first,
                      std::int64_t count, const double* lo, const double* hi, double maxDistance,
                      BucketScratch& scratch) {
  BucketList list;
  // Boxes within the gap tolerance and the widest band (PointSearch::Prune2).
  const double reach = maxDistance + PointSearch::GapBand(store.largestSize());
  list.use = NearestCells(bvh, lo, hi, &scratch.candidates, &scratch.stack, reach, kMaxBucketCandidates, &store) &&
             scratch.candidates.size() <= kMaxBucketCandidates;
  list.lanesSolved = list.use && SolveAffineSimplexLanes(store, points, first, count, maxDistance, scratch);
  if (list.use) GatherSearchedCandidates(store, list.lanesSolved, scratch);
  return list;
}

}  // namespace invmap::engine
