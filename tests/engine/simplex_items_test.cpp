// The affine simplices' vertices the search reads in BVH leaf order: every
// item that is an affine segment, triangle or tetrahedron, and no other,
// with exactly its cell's corner control points; and each such cell's item.
#include <gtest/gtest.h>

#include <vector>

#include "engine/bvh_build.h"
#include "engine/cell_store.h"
#include "engine/simplex_items.h"
#include "invmap/invmap.h"
#include "tests/engine/built_cells.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

engine::Bvh BuildBvhOver(const engine::CellStore& store) {
  std::vector<engine::BvhBox> boxes(store.numSubdivisions());
  for (std::int64_t s = 0; s < store.numSubdivisions(); ++s) {
    for (int k = 0; k < 3; ++k) {
      boxes[s].lo[k] = store.subdivisionBoxLo(s)[k];
      boxes[s].hi[k] = store.subdivisionBoxHi(s)[k];
    }
  }
  return engine::BuildBvh(boxes.data(), static_cast<int>(boxes.size()));
}

TEST(SimplexItemsTest, HoldTheVerticesOfEveryAffineSimplexInLeafOrder) {
  Geometry g = MixedGeometry3();
  g.patches.push_back(BumpySphereMesh(8, 5, {0.3, -0.2, 0.1}, 0.7));
  // A straight, uniformly parametrized polyline: its segments form one
  // affine region (algorithm 6), searched as a block, not as items.
  Patch line;
  line.kind = Patch::Kind::BSpline;
  line.degrees = {1};
  line.knots = {{0, 0, 1, 2, 3, 3}};
  line.counts = {4};
  line.points = {2, 2, 2, 2.5, 2, 2, 3, 2, 2, 3.5, 2, 2};
  g.patches.push_back(line);
  const engine::CellStore store = BuildCells(g);
  const engine::Bvh bvh = BuildBvhOver(store);
  engine::SimplexItems simplices;
  simplices.Build(store, bvh);
  ASSERT_FALSE(simplices.empty());
  int affine = 0, others = 0;
  for (int i = 0; i < bvh.NumBoxes(); ++i) {
    const int item = bvh.Items()[i];
    const std::int64_t cell = store.isRegion(item) ? -1 : store.subdivisionCell(item);
    const bool isSimplex = cell >= 0 && store.solver(cell).isAffineSimplex();
    ASSERT_EQ(simplices.cell(i), isSimplex ? cell : -1) << "item " << i;
    if (cell >= 0) {
      EXPECT_EQ(simplices.item(cell), isSimplex ? i : -1) << "cell " << cell;
    }
    if (!isSimplex) {
      ++others;
      continue;
    }
    ++affine;
    const kernels::CellSolver& solver = store.solver(cell);
    ASSERT_EQ(simplices.paramDim(i), solver.cell().shape.paramDim());
    for (int v = 0; v <= simplices.paramDim(i); ++v) {
      for (int k = 0; k < 3; ++k) EXPECT_EQ(simplices.vertices(i)[3 * v + k], solver.CornerPoint(v)[k]);
    }
  }
  EXPECT_GT(affine, 8 * 5);
  EXPECT_GT(others, 0);
  // Cells inside affine regions are no items of their own; every cell's
  // origin knows its type (the results report its number of parameters).
  int inRegions = 0;
  for (std::int64_t cell = 0; cell < store.size(); ++cell) {
    if (store.inRegion(cell)) {
      ++inRegions;
      EXPECT_EQ(simplices.item(cell), -1) << "cell " << cell;
    }
    EXPECT_EQ(store.origin(cell).type, store.solver(cell).cell().shape.type()) << "cell " << cell;
  }
  EXPECT_EQ(inRegions, 3);
}

TEST(SimplexItemsTest, NoneWithoutAffineSimplices) {
  const engine::CellStore store = BuildCells(NurbsTorus({0, 0, 0}, 2.0, 0.5));
  engine::SimplexItems simplices;
  simplices.Build(store, BuildBvhOver(store));
  EXPECT_TRUE(simplices.empty());
  EXPECT_EQ(simplices.cell(0), -1);
  EXPECT_EQ(simplices.item(0), -1);
}

}  // namespace
}  // namespace invmap::testing
