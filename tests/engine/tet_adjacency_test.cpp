// Face neighbours of tetrahedral cells, used by the engine to walk from the
// previous point's cell toward the next point. Checked against a brute-force
// comparison of every pair of cells' corner triangles.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <vector>

#include "engine/cell_store.h"
#include "invmap/invmap.h"
#include "tests/engine/built_cells.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

using Corner = std::array<double, 3>;

/// The corners of face `face` (opposite corner `face`) as a sorted list.
std::vector<Corner> FaceCorners(const kernels::CellSolver& solver, int face) {
  std::vector<Corner> corners;
  for (int v = 0; v < 4; ++v) {
    if (v == face) continue;
    const double* x = solver.CornerPoint(v);
    corners.push_back({x[0], x[1], x[2]});
  }
  std::sort(corners.begin(), corners.end());
  return corners;
}

TEST(TetAdjacencyTest, NeighboursAreExactlyTheCellsSharingAFace) {
  const engine::CellStore store = BuildCells(QuadraticMesh(false));
  const std::int64_t n = store.size();
  ASSERT_EQ(n, 4 * 4 * 3 * 6);
  const engine::TetAdjacency& adjacency = store.tetAdjacency();
  ASSERT_FALSE(adjacency.empty());
  int boundaryFaces = 0;
  for (std::int64_t a = 0; a < n; ++a) {
    ASSERT_TRUE(store.solver(a).isTetrahedron());
    for (int fa = 0; fa < 4; ++fa) {
      const std::vector<Corner> face = FaceCorners(store.solver(a), fa);
      std::int64_t expected = -1;
      for (std::int64_t b = 0; b < n; ++b) {
        if (b == a) continue;
        for (int fb = 0; fb < 4; ++fb) {
          if (FaceCorners(store.solver(b), fb) == face) expected = b;
        }
      }
      EXPECT_EQ(adjacency.Neighbor(a, fa), expected) << "cell " << a << " face " << fa;
      boundaryFaces += expected < 0 ? 1 : 0;
    }
  }
  // A 4 x 4 x 3 block of cubes, two triangles per boundary square.
  EXPECT_EQ(boundaryFaces, 2 * 2 * (4 * 4 + 4 * 3 + 4 * 3));
}

TEST(TetAdjacencyTest, SurfacesAndHexesHaveNone) {
  const engine::CellStore hexes = BuildCells(QuadraticMesh(true));
  EXPECT_TRUE(hexes.tetAdjacency().empty());
  EXPECT_EQ(hexes.tetAdjacency().Neighbor(0, 0), -1);
}

}  // namespace
}  // namespace invmap::testing
