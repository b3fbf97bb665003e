// Whole-engine inversion on linear triangle meshes of about 100,000
// triangles (a closed bumpy sphere and an open wavy height field, plus a
// planar 2D mesh), against exact point-triangle distances (Ericson) culled
// by the reference's own box tree.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

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

TEST(TriangleMeshTest, PointsOnSliversAmongManyTriangles) {
  // Slivers (the third vertex 1e-5 to 1e-9 of the length off the opposite
  // edge) among well-shaped triangles: enough of them near every point that
  // its search runs the BVH traversal, not only the bucket's lanes. Each
  // query point lies on a sliver (inside it or on an edge), so its distance
  // is zero up to rounding, whichever triangle holds it.
  std::mt19937_64 rng(904);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Patch mesh;
  mesh.kind = Patch::Kind::Mesh;
  mesh.cell = CellType::Tri;
  std::vector<double> queries;
  const auto addVertex = [&](const Vec3& v) {
    mesh.points.insert(mesh.points.end(), v.begin(), v.end());
    return static_cast<std::int64_t>(mesh.points.size() / 3 - 1);
  };
  for (int i = 0; i < 400; ++i) {
    const Vec3 a{{unit(rng), unit(rng), unit(rng)}};
    const Vec3 along = RandomDirection(3, rng);
    Vec3 across = RandomDirection(3, rng);
    const double dot = along[0] * across[0] + along[1] * across[1] + along[2] * across[2];
    for (int k = 0; k < 3; ++k) across[k] -= dot * along[k];
    const double norm = std::sqrt(across[0] * across[0] + across[1] * across[1] + across[2] * across[2]);
    const double length = 0.3 * unit(rng) + 0.05;
    const double height = length * std::pow(10.0, -5.0 - 4.0 * unit(rng));
    const double at = 0.05 + 0.9 * unit(rng);
    Vec3 b, c;
    for (int k = 0; k < 3; ++k) {
      b[k] = a[k] + length * along[k];
      c[k] = a[k] + at * length * along[k] + height * across[k] / norm;
    }
    const std::int64_t ia = addVertex(a), ib = addVertex(b), ic = addVertex(c);
    mesh.cells.insert(mesh.cells.end(), {ia, ib, ic});
    // A point inside the sliver, and the midpoints of its edges.
    double w1 = unit(rng), w2 = unit(rng);
    if (w1 + w2 > 1) w1 = 1 - w1, w2 = 1 - w2;
    for (int k = 0; k < 3; ++k) queries.push_back(a[k] + w1 * (b[k] - a[k]) + w2 * (c[k] - a[k]));
    for (const auto& [from, to] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
      for (int k = 0; k < 3; ++k) queries.push_back(0.5 * (from[k] + to[k]));
    }
    // Well-shaped neighbours around it.
    for (int j = 0; j < 10; ++j) {
      Vec3 v[3];
      for (Vec3& corner : v) {
        for (int k = 0; k < 3; ++k) corner[k] = a[k] + 0.2 * (unit(rng) - 0.5);
      }
      mesh.cells.insert(mesh.cells.end(), {addVertex(v[0]), addVertex(v[1]), addVertex(v[2])});
    }
  }
  Geometry g;
  g.patches.push_back(mesh);
  BuildResult built = Manifold::Build(g);
  ASSERT_TRUE(built.error.empty()) << built.error;
  const std::size_t n = queries.size() / 3;
  Results results;
  std::string message;
  ASSERT_EQ(built.manifold.Invert(PointsView::Interleaved(queries.data(), n, 3), {}, &results, &message), Error::Ok)
      << message;
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_EQ(results.status[i], Status::Found) << "point " << i;
    EXPECT_LE(results.distance[i], 1e-14) << "point " << i << " (sliver " << i / 4 << ")";
  }
}

}  // namespace
}  // namespace invmap::testing
