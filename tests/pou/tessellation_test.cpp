// Tessellations of the surface: closed (every edge in two triangles), and
// every vertex on the surface according to the independent reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "invmap/pou.h"
#include "tests/support/pou_meshes.h"
#include "tests/support/pou_reference.h"

namespace invmap {
namespace {

TEST(PouTessellationTest, ClosedAndOnTheSurface) {
  const testing::TriangleMesh m = testing::Bipyramid(5);
  Patch patch;
  ASSERT_EQ(BuildPouManifold(m.xyz.data(), m.numVertices(), m.triangles.data(), m.numTriangles(), {}, &patch), "");
  PouCharts charts;
  ASSERT_EQ(PouCharts::Create(patch, &charts), "");
  std::vector<double> xyz;
  std::vector<std::int64_t> triangles;
  charts.Tessellate(3, &xyz, &triangles);
  // 10 triangles of 9 each; vertices: 7 corners, 15 edges x 2, 10 x 1 inside.
  EXPECT_EQ(triangles.size() / 3, 90u);
  EXPECT_EQ(xyz.size() / 3, 7u + 30u + 10u);
  std::map<std::pair<std::int64_t, std::int64_t>, int> edges;
  for (std::size_t t = 0; t < triangles.size(); t += 3)
    for (int k = 0; k < 3; ++k) ++edges[{triangles[t + k], triangles[t + (k + 1) % 3]}];
  for (const auto& [edge, count] : edges) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(edges.count({edge.second, edge.first}), 1u) << "edge without its opposite";
  }
  const testing::PouReference reference(patch.points, patch.cells, patch.degrees, patch.chartControlPoints);
  for (std::size_t v = 0; v < xyz.size() / 3; ++v) {
    std::int64_t chart;
    std::complex<double> at;
    EXPECT_LT(reference.Closest(&xyz[3 * v], &chart, &at), 1e-9) << "tessellation vertex " << v;
  }
}

}  // namespace
}  // namespace invmap
