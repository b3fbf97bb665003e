// Buckets whose candidates are affine segments, triangles or tetrahedra are
// solved a cell at a time for all of their points (the vectorized lanes of
// CellSolver::SolveLane). Coarse meshes keep the buckets' candidate lists
// short so that this path carries most points; answers are checked against
// the brute-force reference, and must not depend on the bucket size.
#include <gtest/gtest.h>

#include <vector>

#include "invmap/invmap.h"
#include "tests/support/closest_reference.h"
#include "tests/support/family_runner.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

/// The unit cube cut into n^3 cubes of 6 linear tetrahedra (Kuhn), one mesh patch.
Patch TetCube(int n) {
  Patch patch;
  patch.kind = Patch::Kind::Mesh;
  patch.cell = CellType::Tet;
  auto vertex = [&](int i, int j, int k) { return static_cast<std::int64_t>((k * (n + 1) + j) * (n + 1) + i); };
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        // A slight shear keeps the tets from being axis-aligned.
        const double x = static_cast<double>(i) / n, y = static_cast<double>(j) / n, z = static_cast<double>(k) / n;
        patch.points.insert(patch.points.end(), {x + 0.1 * y, y + 0.05 * z, z + 0.07 * x});
      }
  constexpr int kTets[6][4] = {{0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7}, {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (const auto& tet : kTets)
          for (int c : tet) patch.cells.push_back(vertex(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1)));
  return patch;
}

void RunCoarse(const char* name, const Geometry& g, const QueryMix& mix, std::uint64_t seed) {
  ReferenceGeometry reference(g);
  const QuerySet q = MakeQueries(reference.cells(), g.dimension, reference.size(), mix, seed);
  for (int bucketSize : {32, 7}) {
    InversionOptions options;
    options.bucketSize = bucketSize;
    RunFamily(name, g, q, [&](const double* p) { return reference.Closest(p); }, options);
  }
}

TEST(LaneBucketTest, CoarseTetMeshes) {
  for (int n : {1, 2}) {
    Geometry g;
    g.patches.push_back(TetCube(n));
    QueryMix mix;
    mix.inside = 6000;
    mix.on = 2000;
    mix.near = 4000;
    mix.mid = 2000;
    RunCoarse(n == 1 ? "6 tets" : "48 tets", g, mix, 90 + n);
  }
}

TEST(LaneBucketTest, CoarseTriangleMeshes) {
  Geometry sphere;
  sphere.patches.push_back(BumpySphereMesh(10, 6, {0.2, -0.1, 0.3}, 1.0));
  QueryMix mix;
  mix.on = 3000;
  mix.near = 6000;
  mix.mid = 3000;
  RunCoarse("coarse triangle mesh", sphere, mix, 92);
  Geometry planar;
  planar.dimension = 2;
  planar.patches.push_back(WavyHeightField(4, 2));
  RunCoarse("coarse planar triangle mesh", planar, mix, 93);
}

}  // namespace
}  // namespace invmap::testing
