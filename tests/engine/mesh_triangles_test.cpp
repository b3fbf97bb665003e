// Geometries of triangle meshes alone keep only their vertices and corners
// (engine/mesh_triangles.h): several patches of them answer as the exact
// point-triangle distances (Ericson) say, the manifold costs a small part of
// what a cell with a solver costs, the solvers the rarer paths build on
// demand answer as the closed form does, and the wide tree fitted to the
// vertices by index has the boxes of the one fitted to copies of them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "engine/bvh_build.h"
#include "engine/cell_store.h"
#include "engine/wide_bvh.h"
#include "invmap/invmap.h"
#include "tests/engine/built_cells.h"
#include "tests/support/closest_reference.h"
#include "tests/support/family_runner.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

/// Two triangle-mesh patches side by side; with `empty`, an empty mesh
/// between them (the patch of a cell is then not its mesh's position).
Geometry TwoMeshes(bool empty = false) {
  Geometry g;
  g.patches.push_back(BumpySphereMesh(120, 60, {{0.1, 0.2, -0.1}}, 1.0));
  if (empty) {
    Patch none;
    none.kind = Patch::Kind::Mesh;
    none.cell = CellType::Tri;
    g.patches.push_back(none);
  }
  Patch field = WavyHeightField(90, 3);
  for (std::size_t i = 0; i < field.points.size(); i += 3) field.points[i] += 1.5;
  g.patches.push_back(field);
  return g;
}

TEST(MeshTrianglesTest, PatchesOfTrianglesMatchExactDistances) {
  const Geometry g = TwoMeshes();
  ReferenceGeometry reference(g);
  QueryMix mix;
  mix.on = 2000;
  mix.near = 20000;
  mix.mid = 5000;
  mix.far = 5000;
  const QuerySet q = MakeQueries(reference.cells(), g.dimension, reference.size(), mix, 2801);
  const CheckSummary s = RunFamily("two triangle meshes", g, q, [&](const double* p) { return reference.Closest(p); });
  EXPECT_EQ(s.found, s.points);
}

/// Builds `g` from a copy handed over (Manifold::Build(Geometry&&)), checks
/// every answer against the exact point-triangle distances, expects the
/// bits of the build from `g` itself, and returns the copy as the build
/// left it.
Geometry ExpectMovedInBuildAnswersAsTheReference(const char* name, const Geometry& g, std::uint64_t seed) {
  ReferenceGeometry reference(g);
  QueryMix mix;
  mix.on = 500;
  mix.near = 5000;
  mix.mid = 1000;
  mix.far = 1000;
  const QuerySet q = MakeQueries(reference.cells(), g.dimension, reference.size(), mix, seed);
  Geometry handed = g;
  const BuildResult moved = Manifold::Build(std::move(handed));
  EXPECT_TRUE(moved.error.empty()) << name << ": " << moved.error;
  if (!moved.error.empty()) return handed;
  std::string error;
  const Results results = InvertQueries(moved.manifold, q, {}, &error);
  EXPECT_TRUE(error.empty()) << name << ": " << error;
  const CheckSummary s = CheckResults(g, q, results, [&](const double* p) { return reference.Closest(p); }, {});
  EXPECT_EQ(s.failures, 0) << name << ": " << s.report;
  EXPECT_EQ(s.found, s.points) << name;
  const BuildResult copied = Manifold::Build(g);
  EXPECT_TRUE(copied.error.empty()) << name << ": " << copied.error;
  EXPECT_EQ(CompareBitwise(InvertQueries(copied.manifold, q, {}, &error), results), "") << name;
  EXPECT_EQ(moved.manifold.Info().memoryBytes, copied.manifold.Info().memoryBytes) << name;
  return handed;
}

TEST(MeshTrianglesTest, HandedOverMeshesAnswerAsTheReferenceAndGiveUpTheirArrays) {
  // One patch (its vertex array is moved in) and several (copied, each
  // patch's freed once read).
  Geometry one;
  one.patches.push_back(BumpySphereMesh(80, 40, {{0.1, 0.2, -0.1}}, 1.0));
  for (const auto& [name, g] : {std::pair<const char*, Geometry>{"one mesh", one}, {"meshes", TwoMeshes(true)}}) {
    const Geometry left = ExpectMovedInBuildAnswersAsTheReference(name, g, 2803);
    ASSERT_EQ(left.patches.size(), g.patches.size()) << name;
    for (const Patch& patch : left.patches) {
      EXPECT_TRUE(patch.points.empty()) << name;
      EXPECT_TRUE(patch.cells.empty()) << name;
    }
  }
}

TEST(MeshTrianglesTest, HandedOverGeometriesOfOtherCellsAreReadAsTheyWere) {
  // A triangle mesh beside a quad mesh keeps solvers: nothing is taken.
  Geometry g = TwoMeshes();
  Patch quads;
  quads.kind = Patch::Kind::Mesh;
  quads.cell = CellType::Quad;
  quads.points = {3, 0, 0, 4, 0, 0, 4, 1, 0.2, 3, 1, 0};
  quads.cells = {0, 1, 2, 3};
  g.patches.push_back(quads);
  const Geometry left = ExpectMovedInBuildAnswersAsTheReference("meshes and a quad", g, 2804);
  ASSERT_EQ(left.patches.size(), g.patches.size());
  for (std::size_t p = 0; p < g.patches.size(); ++p) {
    EXPECT_EQ(left.patches[p].points, g.patches[p].points) << "patch " << p;
    EXPECT_EQ(left.patches[p].cells, g.patches[p].cells) << "patch " << p;
  }
}

TEST(MeshTrianglesTest, HandedOverInvalidMeshIsRefusedAndLeftAsItWas) {
  Geometry g = TwoMeshes();
  g.patches[1].cells[7] = static_cast<std::int64_t>(g.patches[1].points.size() / 3);  // one past the last vertex
  Geometry handed = g;
  const BuildResult built = Manifold::Build(std::move(handed));
  EXPECT_EQ(built.code, Error::InvalidArgument);
  EXPECT_EQ(built.problem.patch, 1);
  EXPECT_FALSE(built.manifold.valid());
  EXPECT_EQ(built.error, Manifold::Build(g).error);
  ASSERT_EQ(handed.patches.size(), g.patches.size());
  for (std::size_t p = 0; p < g.patches.size(); ++p) {
    EXPECT_EQ(handed.patches[p].points, g.patches[p].points) << "patch " << p;
    EXPECT_EQ(handed.patches[p].cells, g.patches[p].cells) << "patch " << p;
  }
}

TEST(MeshTrianglesTest, KeepNoObjectPerTriangle) {
  const Geometry g = TwoMeshes();
  const BuildResult built = Manifold::Build(g);
  ASSERT_TRUE(built.error.empty()) << built.error;
  const ManifoldInfo info = built.manifold.Info();
  const std::size_t triangles = (g.patches[0].cells.size() + g.patches[1].cells.size()) / 3;
  ASSERT_EQ(info.cells, triangles);
  // A solver alone is about 360 bytes, and a cell cost about 1,000 with
  // it; the vertices, corners and trees of this mesh (whose height field
  // has more vertices a triangle than a closed mesh) come to about 225.
  EXPECT_LT(static_cast<double>(info.memoryBytes) / triangles, 260.0);
}

TEST(MeshTrianglesTest, SolversBuiltOnDemandAnswerAsTheClosedForm) {
  const Geometry g = TwoMeshes(true);
  const engine::CellStore store = BuildCells(g);
  ASSERT_EQ(store.numPatches(), 3u);
  std::mt19937_64 rng(2802);
  std::uniform_int_distribution<std::int64_t> pick(0, store.size() - 1);
  std::uniform_real_distribution<double> offset(-0.3, 0.3);
  kernels::SolveWorkspace ws;
  for (int trial = 0; trial < 2000; ++trial) {
    const std::int64_t cell = pick(rng);
    const engine::CellOrigin origin = store.origin(cell);
    const Patch& patch = g.patches[origin.patch];
    ASSERT_EQ(patch.cell, CellType::Tri);
    ASSERT_LT(origin.indexInPatch, static_cast<std::int64_t>(patch.cells.size() / 3));
    ASSERT_EQ(store.patchFirstCell(origin.patch) + origin.indexInPatch, cell);
    const double* v[3];
    for (int k = 0; k < 3; ++k) v[k] = &patch.points[3 * patch.cells[3 * origin.indexInPatch + k]];
    const double p[3] = {v[0][0] + offset(rng), v[0][1] + offset(rng), v[0][2] + offset(rng)};
    double s, t, x[3];
    ClosestOnTriangle(p, v[0], v[1], v[2], &s, &t, x);
    const double expected = std::sqrt((p[0] - x[0]) * (p[0] - x[0]) + (p[1] - x[1]) * (p[1] - x[1]) +
                                      (p[2] - x[2]) * (p[2] - x[2]));
    const kernels::CellSolver& solver = store.solver(cell);
    EXPECT_EQ(solver.size(), store.cellSize(cell));
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(solver.CornerPoint(k)[k], v[k][k]);
      EXPECT_LE(solver.boxLo()[k], std::min({v[0][k], v[1][k], v[2][k]}));
      EXPECT_GE(solver.boxHi()[k], std::max({v[0][k], v[1][k], v[2][k]}));
    }
    const kernels::CellSolveResult r = solver.Solve(p, nullptr, &ws);
    EXPECT_NEAR(r.distance, expected, 1e-12) << "cell " << cell;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.closest[k], x[k], 1e-12) << "cell " << cell;
    // Asked again, the same solver.
    EXPECT_EQ(&store.solver(cell), &solver);
  }
}

TEST(MeshTrianglesTest, OrientedBoxesFromIndexedVerticesAreThoseOfTheCopies) {
  const Patch mesh = BumpySphereMesh(90, 45, {{0.1, 0.2, -0.1}}, 1.0);
  const std::size_t count = mesh.cells.size() / 3;
  std::vector<engine::BvhBox> boxes(count);
  for (std::size_t t = 0; t < count; ++t) {
    for (int k = 0; k < 3; ++k) {
      boxes[t].lo[k] = boxes[t].hi[k] = mesh.points[3 * mesh.cells[3 * t] + k];
      for (int v = 1; v < 3; ++v) {
        boxes[t].lo[k] = std::min(boxes[t].lo[k], mesh.points[3 * mesh.cells[3 * t + v] + k]);
        boxes[t].hi[k] = std::max(boxes[t].hi[k], mesh.points[3 * mesh.cells[3 * t + v] + k]);
      }
    }
  }
  const engine::Bvh bvh = engine::BuildBvh(boxes.data(), static_cast<int>(count));
  std::vector<std::int32_t> corners;
  for (const int item : bvh.Items()) {
    for (int v = 0; v < 3; ++v) corners.push_back(static_cast<std::int32_t>(mesh.cells[3 * item + v]));
  }
  const engine::WideBvh copied(
      bvh, 3,
      [&](int t, std::vector<double>* xyz) {
        for (int v = 0; v < 3; ++v) {
          for (int k = 0; k < 3; ++k) xyz->push_back(mesh.points[3 * mesh.cells[3 * t + v] + k]);
        }
      },
      false);
  const engine::WideBvh indexed(bvh, engine::IndexedHulls{mesh.points.data(), corners.data(), 3});
  ASSERT_EQ(copied.Nodes().size(), indexed.Nodes().size());
  ASSERT_GT(copied.Nodes().size(), 100u);
  // Field by field (the node's padding is not part of it).
  int differences = 0;
  for (std::size_t n = 0; n < copied.Nodes().size(); ++n) {
    const engine::WideNode& a = copied.Nodes()[n];
    const engine::WideNode& b = indexed.Nodes()[n];
    differences += std::memcmp(a.lo, b.lo, sizeof(a.lo)) != 0 || std::memcmp(a.hi, b.hi, sizeof(a.hi)) != 0 ||
                   std::memcmp(a.axis, b.axis, sizeof(a.axis)) != 0 ||
                   std::memcmp(a.orientedLo, b.orientedLo, sizeof(a.orientedLo)) != 0 ||
                   std::memcmp(a.orientedHi, b.orientedHi, sizeof(a.orientedHi)) != 0 ||
                   std::memcmp(a.first, b.first, sizeof(a.first)) != 0 ||
                   std::memcmp(a.count, b.count, sizeof(a.count)) != 0;
  }
  EXPECT_EQ(differences, 0);
}

}  // namespace
}  // namespace invmap::testing
