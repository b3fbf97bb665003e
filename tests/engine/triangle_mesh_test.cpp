// Whole-engine inversion on linear triangle meshes of about 100,000
// triangles (a closed bumpy sphere and an open wavy height field, plus a
// planar 2D mesh), against exact point-triangle distances (Ericson) culled
// by the reference's own box tree.
#include <gtest/gtest.h>

#include <random>

#include "invmap/invmap.h"
#include "tests/support/closest_reference.h"
#include "tests/support/family_runner.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

void RunMesh(const char* name, const Geometry& g, QueryMix mix, std::uint64_t seed, int centrePoints,
             const Vec3& centre) {
  ReferenceGeometry reference(g);
  QuerySet q = MakeQueries(reference.cells(), g.dimension, reference.size(), mix, seed);
  // Points near the centre of the sphere: near-ties with thousands of triangles.
  std::mt19937_64 rng(seed + 1);
  for (int i = 0; i < ScaledCount(centrePoints); ++i) {
    const Vec3 dir = RandomDirection(g.dimension, rng);
    const double r = 0.05 * std::uniform_real_distribution<double>(0.0, 1.0)(rng);
    const Vec3 p{{centre[0] + r * dir[0], centre[1] + r * dir[1], centre[2] + r * dir[2]}};
    q.Add(p.data(), "centre");
  }
  const CheckSummary s = RunFamily(name, g, q, [&](const double* p) { return reference.Closest(p); });
  EXPECT_EQ(s.found, s.points);
}

QueryMix SurfaceMix() {
  QueryMix mix;
  mix.on = 5000;
  mix.near = 55000;
  mix.mid = 20000;
  mix.far = 20000;
  return mix;
}

TEST(TriangleMeshTest, BumpySphere) {
  Geometry g;
  g.patches.push_back(BumpySphereMesh(320, 158, {{0.1, 0.2, -0.1}}, 1.0));
  ASSERT_GE(g.patches[0].cells.size() / 3, 100000u);
  QueryMix mix = SurfaceMix();
  mix.near -= 1000;
  RunMesh("bumpy sphere mesh", g, mix, 901, 1000, {{0.1, 0.2, -0.1}});
}

TEST(TriangleMeshTest, WavyHeightField) {
  Geometry g;
  g.patches.push_back(WavyHeightField(224, 3));
  ASSERT_GE(g.patches[0].cells.size() / 3, 100000u);
  RunMesh("wavy height field mesh", g, SurfaceMix(), 902, 0, {});
}

TEST(TriangleMeshTest, PlanarMesh2D) {
  Geometry g;
  g.dimension = 2;
  g.patches.push_back(WavyHeightField(100, 2));
  QueryMix mix;
  mix.on = 5000;
  mix.near = 10000;
  mix.mid = 5000;
  mix.far = 5000;
  mix.inside = 5000;
  RunMesh("planar 2D mesh", g, mix, 903, 0, {});
}

}  // namespace
}  // namespace invmap::testing
