// Inside hits of a bucket's points in a mesh of curved tetrahedra, solved
// cell by cell in SIMD lanes (docs/how-it-works.md, "Lanes: many points on
// one cell at once"): each point is located by a walk across the faces of
// the cells' straight corner tetrahedra (no Newton solve on the way), then
// the points that landed in one cell are solved inside it together
// (CellSolver::SolveInsideLane). A point inside a volume cell is its own
// closest point, the certified global minimum. A point the walk does not
// place, or that its cell does not hold, is left to the per-point search.
#pragma once

#include <cstdint>
#include <memory>
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
  std::unique_ptr<bool[]> inside;
  int insideCapacity = 0;
};

/// True when a geometry's buckets go through SolveInsideByLanes: 3D volume
/// cells, unless the search must be the point's alone
/// (InversionOptions::pointwise).
inline bool UsesVolumeLanes(const CellStore& store, bool pointwise) {
  return !pointwise && store.hasVolumeCells() && store.dimension() == 3;
}

/// True for a cell the lanes solve inside, and start a walk from: a curved
/// tetrahedron (an affine one is solved in closed form by the per-point
/// search, as fast).
inline bool IsLaneTetrahedron(const CellStore& store, std::int64_t cell) {
  if (cell < 0 || store.inRegion(cell)) return false;
  const kernels::CellSolver& solver = store.solver(cell);
  return solver.isTetrahedron() && !solver.isAffineSimplex();
}

/// Solves points 1 .. count - 1 of a bucket (coord[k][0 .. count), in
/// Morton order; point 0 is the caller's) inside the curved tetrahedral
/// cells of `store` that hold them. The walk of point 1 starts at `start`
/// (point 0's answer cell, IsLaneTetrahedron), each later one's
/// where the previous walk ended, and takes at most `maxSteps` steps. Every
/// answer depends on the bucket's points alone.
void SolveInsideByLanes(const CellStore& store, const double* const coord[3], int count, std::int64_t start,
                        int maxSteps, VolumeLanes* lanes);

}  // namespace invmap::engine
