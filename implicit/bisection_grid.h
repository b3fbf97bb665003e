// A conforming simplicial grid that bisects edges: the mesh side of longest
// refinable edge bisection (section 4 of
// docs/grids.md).
//
// Bisecting edge (a, b) at its midpoint m splits every cell around the edge
// into two children that keep the parent's vertex order: the first has m in
// b's slot, the second m in a's slot, so orientations are preserved (the
// reference implementation does the same, and cell counts depend on it
// through the order in which a cell's equally long edges are considered).
// The first child reuses the parent's index with its version bumped; the
// second is appended.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "invmap/implicit.h"

namespace invmap::implicit {

template <int N>
class BisectionGrid {
 public:
  using Cell = std::array<std::uint32_t, N + 1>;
  static constexpr int kEdges = N == 3 ? 6 : 3;
  /// Local edge order: tetrahedron (v0v1, v1v2, v2v0, v0v3, v1v3, v2v3),
  /// triangle (v0v1, v1v2, v2v0).
  static constexpr int kEdgeVertex[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};

  /// `mesh` must be conforming, of dimension N, with valid indices.
  explicit BisectionGrid(const SimplexMesh& mesh);

  std::size_t numVertices() const { return coordinates_.size() / 3; }
  std::size_t numCells() const { return cells_.size(); }
  const Cell& cell(std::uint32_t c) const { return cells_[c]; }
  std::uint32_t version(std::uint32_t c) const { return versions_[c]; }
  const double* point(std::uint32_t v) const { return coordinates_.data() + 3 * static_cast<std::size_t>(v); }

  /// The longest edge of cell c (the first in local order among equally long
  /// ones) and its squared length.
  int LongestEdge(std::uint32_t c, double* length2) const;

  /// Bisects the edge between vertices a and b; appends the indices of all
  /// children (both children of each cell around the edge) to `children`.
  /// Returns false (and changes nothing) when no cell has that edge.
  bool Bisect(std::uint32_t a, std::uint32_t b, std::vector<std::uint32_t>* children);

  /// The grid as a SimplexMesh (cells in index order).
  SimplexMesh ToMesh() const;

 private:
  std::vector<double> coordinates_;
  std::vector<Cell> cells_;
  std::vector<std::uint32_t> versions_;
  /// The cells around each vertex (any order).
  std::vector<std::vector<std::uint32_t>> cellsOfVertex_;
  std::vector<std::uint32_t> ring_;  ///< Scratch: the cells around the edge being bisected.
};

extern template class BisectionGrid<2>;
extern template class BisectionGrid<3>;

}  // namespace invmap::implicit
