// The points of a bucket on a geometry of curves and surfaces, solved cell
// by cell in SIMD lanes (CellSolver::SolveLane) instead of point by point
// (docs/how-it-works.md, "Lanes: many points on one cell at once"):
//  1. each point's cell and start are predicted from the bucket's first
//     answer (engine/warm_start.h), and each predicted cell is solved for
//     all the points predicted in it;
//  2. each point's traversal of the 4-ary tree, cut at that answer's
//     distance, lists the other cells that could be nearer, without
//     solving them;
//  3. each listed cell is solved for all the points that listed it, each
//     lane bounded by its point's best distance so far (the nets' lower
//     bounds and the tangent-plane exclusion drop most lanes at once).
// A cell that could beat a point's final answer has a lower bound below it,
// so below the distance the traversal was cut at: every such cell is
// listed, and each point's answer is the certified global minimum.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "engine/bvh_build.h"
#include "engine/cell_store.h"
#include "engine/simplex_items.h"
#include "engine/warm_start.h"
#include "engine/wide_bvh.h"

namespace invmap::engine {

/// Per-bucket answers and scratch, reused across buckets (one per thread).
struct BucketLanes {
  /// Per point: true when `cell` and `result` are its final answer (cell
  /// -1: none within the gap tolerance). Otherwise the per-point search
  /// answers it, going on from `cell` and `result` when cell >= 0 (the
  /// predicted cell's answer).
  std::vector<char> settled;
  std::vector<std::int64_t> cell;
  std::vector<kernels::CellSolveResult> result;
  /// Per point: Newton iterations over every cell solved for it.
  std::vector<int> iterations;

  // Scratch.
  std::vector<std::pair<std::int64_t, int>> pairs;  ///< (subdivision or cell, point)
  std::vector<double> pairStarts;                   ///< 3 per pair of step 1
  std::vector<double> stackBound2;
  std::vector<std::int32_t> stackFirst, stackCount;
  std::vector<double> coord[3], start[3], bound2, ref[3], closest[3], distance;
  std::vector<kernels::PointStatus> status;
  std::vector<int> laneIterations;
  kernels::SolveWorkspace workspace;
};

/// True when a geometry's buckets go through SolveBucketInLanes: curves and
/// surfaces (no volume cells), unless the search must be the point's alone
/// (InversionOptions::pointwise).
inline bool UsesBucketLanes(const CellStore& store, bool pointwise) { return !pointwise && !store.hasVolumeCells(); }

/// True when the bucket's points after one answered in `cell` go through
/// SolveBucketInLanes: the predictions start from a curved cell (an affine
/// simplex, a region's cell or a trimmed cell leaves them to the per-point
/// search, which has closed forms and the face's region for those). An
/// affine simplex is told by `simplices` first: on a large mesh its solver
/// is a cold read, once per point of every bucket.
inline bool StartsBucketLanes(const CellStore& store, const SimplexItems& simplices, std::int64_t cell) {
  return cell >= 0 && simplices.item(cell) < 0 && !store.inRegion(cell) && !store.isAffineSimplex(cell) &&
         !store.solver(cell).trim();
}

/// Solves points 1 .. count - 1 of a bucket (coord[k][0 .. count), 2D
/// without coord[2]; point 0 is the caller's, answered `first`) of a
/// geometry without volume cells. `maxDistance`: the gap tolerance. Answers
/// land in `lanes` (entry 0 untouched, not settled). A point is left to the
/// per-point search when it is not finite, its predicted cell is not one the
/// lanes start from (StartsBucketLanes) or its start lies beyond that cell's
/// domain, that cell has no answer within the gap tolerance, or it lists
/// more than 48 other cells. The answers depend on the bucket alone.
void SolveBucketInLanes(const CellStore& store, const WideBvh& wide, const Bvh& bvh, const SimplexItems& simplices,
                        const double* const coord[3], int count, const WarmStart& first, double maxDistance,
                        BucketLanes* lanes);

}  // namespace invmap::engine
