// Inside hits of a bucket's points in a tetrahedral mesh, solved cell by
// cell in SIMD lanes: each point is located by a walk across the faces of
// the cells' straight corner tetrahedra (no Newton solve on the way), then
// the points that landed in one cell are solved inside it together
// (CellSolver::SolveInsideLane). A point the walk does not place, or that
// its cell does not hold, is left to the per-point search.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "engine/cell_store.h"

namespace invmap::engine {

/// Per-bucket results and scratch, reused across buckets (one per thread).
struct VolumeLanes {
  /// Per point: the cell that holds it (its answer then in `result`), or -1.
  std::vector<std::int64_t> cell;
  std::vector<kernels::CellSolveResult> result;

  // Scratch: (cell, point) pairs, and one cell's lanes.
  std::vector<std::pair<std::int64_t, int>> order;
  std::vector<double> coord[3], ref[3], closest[3], distance;
  std::vector<kernels::PointStatus> status;
  std::vector<int> iterations;
  std::vector<char> inside;
};

/// Solves the points coord[k][0 .. count) (a bucket, in Morton order; 3D,
/// finite) inside the tetrahedral cells of `store` that hold them. The walk
/// of each point starts at the cell the previous point's walk ended in (the
/// first point's at `start`, -1 for none) and takes at most `maxSteps`
/// steps. Every answer depends on the bucket's points alone.
void SolveInsideByLanes(const CellStore& store, const double* const coord[3], int count, std::int64_t start,
                        int maxSteps, VolumeLanes* lanes);

}  // namespace invmap::engine
