// Face neighbours of the volume cells of a manifold (tetrahedra, hexahedra,
// wedges, of any order), for point location by walking: from the previous
// point's cell across the face the point lies beyond, instead of a
// traversal of the BVH.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/hex_frames.h"
#include "engine/walk_start_grid.h"
#include "kernels/cell_solver.h"

namespace invmap::engine {

class FaceAdjacency {
 public:
  /// Pairs the faces (kernels/reference_faces.h) of every volume cell (3D)
  /// whose corner control points coincide exactly, across patches and cell
  /// types too (a wedge's triangle with a tetrahedron's). A face shared by
  /// more than two cells (a non-conforming or duplicated mesh) gets no
  /// neighbour. Builds the walk's start grid over the same cells, and the
  /// affine hexahedra's frames (engine/hex_frames.h). Nothing
  /// for a manifold of 2^31 cells or more.
  void Build(const std::vector<kernels::CellSolver>& solvers, int maxThreads);

  /// The cell across face `face` of volume cell `cell` (numbered as
  /// kernels::NumFaces counts them), or -1 (boundary, not a volume cell, or
  /// no adjacency built).
  std::int64_t Neighbor(std::int64_t cell, int face) const {
    return neighbors_.empty() ? -1 : neighbors_[static_cast<std::size_t>(cell) * stride_ + face];
  }
  bool empty() const { return neighbors_.empty(); }
  /// Where a walk to a point starts (engine/walk_start_grid.h).
  const WalkStartGrid& startGrid() const { return startGrid_; }
  /// The affine hexahedra as the walk reads them (engine/hex_frames.h).
  const HexFrames& frames() const { return frames_; }
  std::size_t MemoryBytes() const {
    return neighbors_.capacity() * sizeof(std::int32_t) + startGrid_.MemoryBytes() + frames_.MemoryBytes();
  }

 private:
  int stride_ = 0;  // the most faces of a volume cell of the manifold
  // stride_ per cell; 32 bits (half the memory the walk reads in random
  // order; a manifold of 2^31 cells or more gets no neighbours).
  std::vector<std::int32_t> neighbors_;
  WalkStartGrid startGrid_;
  HexFrames frames_;
};

}  // namespace invmap::engine
