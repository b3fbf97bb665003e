// Inversion onto partition-of-unity surfaces through the public API, against
// the independent reference of tests/support/pou_reference.h (dense sampling
// of every chart and a polished local solve), on meshes with vertices of
// valence 3 to 8, a torus and a genus-2 surface: the distance is never
// larger than the reference's, agrees with it, and the reported chart and
// coordinates evaluate to the reported point.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "invmap/invmap.h"
#include "invmap/pou.h"
#include "tests/support/pou_meshes.h"
#include "tests/support/pou_reference.h"

namespace invmap {
namespace {

double Diagonal(const std::vector<double>& xyz) {
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (std::size_t i = 0; i < xyz.size(); i += 3)
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min(lo[c], xyz[i + c]);
      hi[c] = std::max(hi[c], xyz[i + c]);
    }
  return std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
}

// Disabled: the search is too slow to complete here and, with a budget, wrong
// (docs/manifold.md, "Status"). Run it with --gtest_also_run_disabled_tests.
TEST(PouInversionTest, MatchesTheIndependentReference) {
  std::vector<testing::TriangleMesh> meshes;
  for (int n = 3; n <= 8; ++n) meshes.push_back(testing::Bipyramid(n));
  meshes.push_back(testing::Torus(8, 6, 2.0, 0.7));
  meshes.push_back(testing::GenusTwo(2));
  std::mt19937_64 random(17);
  for (const auto& m : meshes) {
    Patch patch;
    PouOptions options;
    options.base = PouBase::PnTriangles;
    ASSERT_EQ(BuildPouManifold(m.xyz.data(), m.numVertices(), m.triangles.data(), m.numTriangles(), options, &patch),
              "");
    Geometry geometry;
    geometry.patches.push_back(patch);
    BuildResult built = Manifold::Build(geometry);
    ASSERT_EQ(built.error, "") << m.name;
    PouCharts charts;
    ASSERT_EQ(PouCharts::Create(patch, &charts), "");
    const testing::PouReference reference(patch.points, patch.cells, patch.degrees, patch.chartControlPoints);
    const double size = Diagonal(m.xyz);
    // Points near the surface: a random point of a random chart, moved off it.
    std::vector<double> points;
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (int i = 0; i < 6; ++i) {
      const std::int64_t v = static_cast<std::int64_t>(random() % m.numVertices());
      const double r = 0.5 * reference.radius(v);
      double p[3];
      reference.Evaluate(v, {r * unit(random), r * unit(random)}, p);
      for (int c = 0; c < 3; ++c) points.push_back(p[c] + 0.08 * size * unit(random));
    }
    Results results;
    ASSERT_EQ(built.manifold.Invert(PointsView::Interleaved(points.data(), points.size() / 3, 3), {}, &results),
              Error::Ok);
    for (std::size_t i = 0; i < points.size() / 3; ++i) {
      std::int64_t chart;
      std::complex<double> at;
      const double expected = reference.Closest(&points[3 * i], &chart, &at);
      ASSERT_EQ(results.status[i], Status::Found);
      EXPECT_EQ(results.patch[i], 0);
      EXPECT_LE(results.distance[i], expected + 1e-9 * size) << m.name << " point " << i;
      EXPECT_NEAR(results.distance[i], expected, 1e-6 * size) << m.name << " point " << i;
      ChartJet jet;
      ASSERT_TRUE(charts.Evaluate(results.cell[i], results.params[3 * i], results.params[3 * i + 1], &jet));
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(jet.point[c], results.closest[3 * i + c], 1e-12 * size);
      double exact[3];
      reference.Evaluate(results.cell[i], {results.params[3 * i], results.params[3 * i + 1]}, exact);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(exact[c], results.closest[3 * i + c], 1e-12 * size);
    }
  }
}

}  // namespace
}  // namespace invmap
