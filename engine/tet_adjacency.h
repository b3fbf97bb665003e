// Face neighbours of the tetrahedral cells of a manifold, for point location
// by walking: from the previous point's cell across the face the point lies
// beyond, instead of a traversal of the BVH.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/cell_solver.h"

namespace invmap::engine {

class TetAdjacency {
 public:
  /// Pairs the faces of every tetrahedral cell (3D) whose corner control
  /// points coincide exactly, across patches too. A face shared by more than
  /// two cells (a non-conforming or duplicated mesh) gets no neighbour.
  void Build(const std::vector<kernels::CellSolver>& solvers, int maxThreads);

  /// The cell across face `face` (opposite corner `face`) of tetrahedron
  /// `cell`, or -1 (boundary, not a tetrahedron, or no adjacency built).
  std::int64_t Neighbor(std::int64_t cell, int face) const {
    return neighbors_.empty() ? -1 : neighbors_[static_cast<std::size_t>(cell) * 4 + face];
  }
  bool empty() const { return neighbors_.empty(); }
  std::size_t MemoryBytes() const { return neighbors_.capacity() * sizeof(std::int64_t); }

 private:
  std::vector<std::int64_t> neighbors_;  // 4 per cell
};

}  // namespace invmap::engine
