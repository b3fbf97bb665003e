// Where a point's walk through a volume mesh starts: a uniform grid over the
// volume cells' box holding, per grid cell, a volume cell at (or nearest to)
// the grid cell's centre, as VTK's cell locators keep cells per bin. A walk
// from there crosses about one cell to reach the point, where one from the
// previous point's cell crossed three on random points (their Morton order
// jumps between far regions now and then). The grid only proposes the
// start: the walk's answers are inside solves' exact ones, and a point it
// does not place goes to the full search, so a poor start costs time, never
// an answer.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/cell_solver.h"

namespace invmap::engine {

class WalkStartGrid {
 public:
  /// Builds the grid over the cells for which `walkable` is true (volume
  /// cells with face neighbours), about 27 grid cells per such cell, at
  /// most 2^24. Each grid cell holds the tetrahedron (by its corner
  /// tetrahedron) or affine hexahedron or wedge that contains its centre,
  /// deepest first, or else the other volume cell whose control-point box
  /// is the most centred on it; the
  /// lowest index on a tie, so the grid depends on the geometry alone. A
  /// grid cell left empty (along the mesh's slanted or curved boundary,
  /// where part of it may still lie in the mesh) takes a face neighbour's
  /// entry, twice over.
  void Build(const std::vector<kernels::CellSolver>& solvers, const std::vector<bool>& walkable);

  /// The start cell for point `p` (3 coordinates): the entry of the grid
  /// cell holding p, or of the nearest one for a point outside the grid's
  /// box; -1 when that grid cell has no cell or there is no grid.
  std::int64_t StartCell(const double* p) const {
    return cells_.empty() ? -1 : cells_[SlotOf(p)];
  }

  /// Requests from memory the entry StartCell(p) will read.
  void Prefetch(const double* p) const {
    if (!cells_.empty()) __builtin_prefetch(&cells_[SlotOf(p)]);
  }

  bool empty() const { return cells_.empty(); }
  std::size_t MemoryBytes() const { return cells_.capacity() * sizeof(std::int32_t); }

 private:
  /// Where grid cell (x, y, z) is kept: in tiles of 4 x 4 x 4 grid cells
  /// (256 bytes), so that the grid cells of nearby points, which come one
  /// after the other in the batch's Morton order, share cache lines (a
  /// plain x-fastest layout put each in a line of its own and made the
  /// grid's read half the walk's time on random points in tetrahedra).
  std::size_t Slot(std::int64_t x, std::int64_t y, std::int64_t z) const {
    const std::int64_t tile = ((z >> 2) * tiles_[1] + (y >> 2)) * tiles_[0] + (x >> 2);
    return static_cast<std::size_t>(tile * 64 + (z & 3) * 16 + (y & 3) * 4 + (x & 3));
  }

  /// The slot of the grid cell holding point `p`; NaN and points beyond
  /// the box clamp to the boundary's grid cells.
  std::size_t SlotOf(const double* p) const {
    std::int64_t at[3];
    for (int k = 0; k < 3; ++k) {
      const double t = (p[k] - lo_[k]) * inverseStep_[k];
      at[k] = t >= 1.0 ? (t < count_[k] ? static_cast<std::int64_t>(t) : count_[k] - 1) : 0;
    }
    return Slot(at[0], at[1], at[2]);
  }

  /// Gives each empty grid cell the entry of a face neighbour that has one
  /// (the first of -x, +x, -y, +y, -z, +z), from the grid as it was before
  /// the pass, kFillPasses times.
  void FillEmptyFromNeighbors();

  double lo_[3] = {0, 0, 0};
  double inverseStep_[3] = {0, 0, 0};
  std::int64_t count_[3] = {0, 0, 0};
  std::int64_t tiles_[3] = {0, 0, 0};  ///< Tiles along each axis.
  std::vector<std::int32_t> cells_;  ///< by Slot; -1 where no cell is near
};

}  // namespace invmap::engine
