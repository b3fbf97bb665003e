// The blended parametrizations agree on every overlap: theta_v(p) equals
// theta_u(phi_uv(p)) for every pair of neighbouring charts and points of
// their gluing domain, with all three base surfaces and valences 3 to 8.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "pou/pou_surface.h"
#include "tests/support/pou_meshes.h"

namespace invmap::pou {
namespace {

using testing::TriangleMesh;

std::vector<TriangleMesh> Meshes() {
  std::vector<TriangleMesh> meshes;
  for (int n = 3; n <= 8; ++n) meshes.push_back(testing::Bipyramid(n));
  meshes.push_back(testing::Icosphere(1, 1.0));
  meshes.push_back(testing::Torus(9, 7, 2.0, 0.7));
  meshes.push_back(testing::GenusTwo(2));
  return meshes;
}

class ConsistencyTest : public ::testing::TestWithParam<BaseKind> {};

TEST_P(ConsistencyTest, ChartsAgreeOnEveryOverlap) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (const TriangleMesh& m : Meshes()) {
    PouSurface surface;
    ASSERT_EQ(surface.Build(m.xyz.data(), m.numVertices(), m.triangles.data(), m.numTriangles(), GetParam(), 0), "")
        << m.name;
    const double size = m.diagonal();
    double worst = 0.0;
    int overlaps = 0;
    for (std::int64_t v = 0; v < surface.numCharts(); ++v) {
      const double r = surface.radius(v);
      for (int sample = 0; sample < 200; ++sample) {
        const double x = r * unit(random), y = r * unit(random);
        if (std::hypot(x, y) >= r) continue;
        double p[3];
        surface.EvaluatePoint(v, x, y, p);
        for (int edge = 0; edge < surface.valence(v); ++edge) {
          double qx, qy;
          if (!surface.Transition(v, edge, x, y, &qx, &qy)) continue;
          double q[3];
          surface.EvaluatePoint(surface.mesh().neighbor(v, edge), qx, qy, q);
          worst = std::max(worst, std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]));
          ++overlaps;
        }
      }
    }
    EXPECT_GT(overlaps, 100) << m.name;
    EXPECT_LE(worst, 1e-12 * size) << m.name << ": theta_v(p) and theta_u(phi_uv(p)) differ by " << worst;
  }
}

INSTANTIATE_TEST_SUITE_P(Bases, ConsistencyTest,
                         ::testing::Values(BaseKind::Flat, BaseKind::PnTriangles, BaseKind::Loop));

}  // namespace
}  // namespace invmap::pou
