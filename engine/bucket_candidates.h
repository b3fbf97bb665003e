// Algorithm 3 once per bucket (docs/how-it-works.md, "Cull per bucket"): the
// candidate cells a bucket of points shares, the lanes solved on its affine
// simplices, and the part of the list each point still searches itself.
#pragma once

#include <cstddef>
#include <cstdint>

#include "engine/box_distance.h"
#include "engine/bucket_scratch.h"
#include "engine/bvh_build.h"
#include "engine/cell_store.h"
#include "engine/query_points.h"

namespace invmap::engine {

/// Candidates of the bucket's list beyond this many are better found per
/// point: far from the geometry, algorithm 3's box upper bounds admit most of
/// the cells, and a best-first traversal that tightens with each solved cell
/// visits far fewer. The list's traversal gives up as soon as it has
/// collected more than this many, though the final bound might have trimmed
/// some of them: on every workload of more than a few dozen cells (the bicubic
/// surface, the triangle mesh) nearly all lists are given up, so the attempt
/// is kept short: collecting twice as many cost 1.5% (mesh) to 3% (surface)
/// of the time, four times as many 3 to 7%.
constexpr std::size_t kMaxBucketCandidates = 24;

/// True for a candidate that SolveAffineSimplexLanes solves (an affine simplex).
inline bool SolvedAsLanes(const CellStore& store, std::int64_t subdivision) {
  return store.affineSimplexCell(subdivision) >= 0;
}

/// What culling a bucket found.
struct BucketList {
  /// The bucket's points search scratch.candidates (not the BVH): the list
  /// is at most kMaxBucketCandidates long.
  bool use = false;
  /// SolveAffineSimplexLanes solved the list's affine simplices for every
  /// point of the bucket (their best in scratch.laneBestCell, scratch.laneBest).
  bool lanesSolved = false;
};

/// Algorithm 3 once for the bucket of points [first, first + count) of
/// `points`, whose finite points span the box [lo, hi]: the candidate list
/// into scratch.candidates (NearestCells over `bvh`, built over the
/// subdivisions of `store`), its affine simplices solved as lanes, and the
/// candidates each point still searches with their boxes into
/// scratch.searched and scratch.searchedBox. The result depends on the
/// bucket alone.
BucketList CullBucket(const CellStore& store, const Bvh& bvh, const QueryPoints& points, std::int64_t first,
                      std::int64_t count, const double* lo, const double* hi, double maxDistance,
                      BucketScratch& scratch);

/// Squared distance from a point to the box of searched candidate j (an
/// index into scratch.searched).
inline double SearchedBoxDistance2(const BucketScratch& scratch, std::size_t j, const double* p, int dim) {
  double d2 = 0.0;
  for (int k = 0; k < dim; ++k) {
    const double d = AxisGap(scratch.searchedBox[k][j], p[k], scratch.searchedBox[3 + k][j]);
    d2 += d * d;
  }
  return d2;
}

}  // namespace invmap::engine
