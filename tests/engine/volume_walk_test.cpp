// The walk across the faces of volume meshes (PointSearch::TryInsideByWalk,
// engine/face_adjacency.h) on hexahedra, wedges and mixed meshes, straight
// and curved: called directly, it reaches a cell several faces away and
// answers there exactly; in the batch, where it places most inside points,
// every answer (inside, on shared faces and edges, outside) is the
// brute-force reference's (tests/support/closest_reference.h) and the same
// bits for any thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "engine/bucket_scratch.h"
#include "engine/point_search.h"
#include "engine/search_index.h"
#include "invmap/invmap.h"
#include "tests/support/closest_reference.h"
#include "tests/support/family_runner.h"
#include "tests/support/reference_cell.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

/// A curved map of the unit cube: trilinear cells are curved under it.
Vec3 Warp(double a, double b, double c) {
  return Vec3{a + 0.15 * b * b + 0.05 * c, b + 0.1 * std::sin(2 * a) + 0.05 * c * a, c + 0.1 * a * b};
}

/// A shear: linear cells stay affine (parallelepipeds, straight prisms).
Vec3 Shear(double a, double b, double c) {
  return Vec3{a + 0.2 * b + 0.1 * c, 0.1 * a + 0.9 * b - 0.05 * c, -0.1 * a + 0.15 * b + 1.1 * c};
}

/// Warp with the inner vertices of a 6 x 5 x 4 grid moved by up to 30% of a
/// cell: twisted hexahedra whose faces are not planar.
Vec3 Distorted(double a, double b, double c) {
  Vec3 x = Warp(a, b, c);
  const bool inner = a > 0 && a < 1 && b > 0 && b < 1 && c > 0 && c < 1;
  if (inner) {
    x[0] += 0.3 / 6 * std::sin(37 * a + 11 * b + 5 * c);
    x[1] += 0.3 / 5 * std::sin(13 * a + 29 * b + 7 * c);
    x[2] += 0.3 / 4 * std::sin(17 * a + 3 * b + 31 * c);
  }
  return x;
}

/// Quadratic wedges [2, 2], curved: each linear wedge of a GridMesh of
/// 6 x 5 x 4 prisms under `Bend`, its control points the bent images of the
/// points of the straight wedge at their reference locations (a conforming
/// BezierCells patch: neighbours compute their shared face's control points
/// from the same vertices).
Geometry CurvedWedges() {
  const auto bend = [](const Vec3& x) {
    return Vec3{x[0] + 0.1 * std::sin(3 * x[1]), x[1] + 0.08 * std::cos(2 * x[0] + x[2]), x[2] + 0.1 * x[0] * x[1]};
  };
  const Patch grid = GridMesh(CellType::Wedge, 3, 6, 5, 4, Warp);
  const std::vector<std::array<double, 3>> refs = ControlPointRefLocations(kernels::CellType::Wedge, {2, 2, 0});
  Geometry g;
  g.dimension = 3;
  Patch mesh;
  mesh.kind = Patch::Kind::BezierCells;
  mesh.cellOffsets.push_back(0);
  for (std::size_t c = 0; c + 6 <= grid.cells.size(); c += 6) {
    const double* v[6];
    for (int k = 0; k < 6; ++k) v[k] = &grid.points[static_cast<std::size_t>(grid.cells[c + k]) * 3];
    for (const std::array<double, 3>& r : refs) {
      // The straight wedge: bottom triangle v0 v1 v2 at w = 0, top v3 v4 v5.
      const double l0 = 1 - r[0] - r[1];
      Vec3 x;
      for (int e = 0; e < 3; ++e) {
        x[e] = (1 - r[2]) * (l0 * v[0][e] + r[0] * v[1][e] + r[1] * v[2][e]) +
               r[2] * (l0 * v[3][e] + r[0] * v[4][e] + r[1] * v[5][e]);
      }
      const Vec3 y = bend(x);
      mesh.points.insert(mesh.points.end(), y.begin(), y.end());
    }
    mesh.cellTypes.push_back(CellType::Wedge);
    mesh.cellDegrees.insert(mesh.cellDegrees.end(), {2, 2, 0});
    mesh.cellOffsets.push_back(static_cast<std::int64_t>(mesh.points.size() / 3));
  }
  g.patches.push_back(std::move(mesh));
  return g;
}

Geometry Mesh(CellType type, int dim, const std::function<Vec3(double, double, double)>& f) {
  Geometry g;
  g.dimension = dim;
  g.patches.push_back(GridMesh(type, dim, 6, 5, dim == 3 ? 4 : 0, f));
  return g;
}

/// From the centre of cell `from`, the walk alone (no BVH search) finds the
/// image of `ref` in cell `to` inside `to`, exactly, after trying at least
/// `minCells` cells.
void ExpectWalkReaches(const char* name, const Geometry& g, std::int64_t from, std::int64_t to,
                       std::array<double, 3> ref, std::size_t minCells) {
  const engine::SearchIndex index = engine::SearchIndex::Build(g, 1);
  const engine::CellStore& store = index.cells();
  const std::vector<PatchCell> cells = GeometryCells(g);
  ASSERT_EQ(static_cast<std::int64_t>(cells.size()), store.size()) << name;
  double p[3] = {0, 0, 0};
  RefEvaluate(cells[to].cell, ref.data(), p);
  const std::array<double, 3> start = RefDomainCenter(cells[from].cell.type);
  engine::BucketScratch scratch;
  engine::PointSearch search(store, index.simplices(), p, scratch, from, start.data(),
                             std::numeric_limits<double>::infinity());
  search.TryInsideByWalk(index.bvh(), from);
  EXPECT_TRUE(search.inside) << name;
  EXPECT_EQ(search.bestCell, to) << name;
  EXPECT_GE(search.tried.size(), minCells) << name;
  EXPECT_LE(search.bestResult.distance, 1e-12) << name;
  // The answer's parameters are the point's preimage (the tests' own evaluation).
  double back[3] = {0, 0, 0};
  RefEvaluate(cells[to].cell, search.bestResult.ref, back);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(back[k], p[k], 1e-12) << name;
}

/// Cell (i, j, k) of a GridMesh of 6 x 5 x 4 cubes, `perCube` cells each.
std::int64_t GridCell(int i, int j, int k, int perCube = 1) { return ((k * 5 + j) * 6 + i) * perCube; }

TEST(VolumeWalkTest, WalksAcrossHexahedraAndWedges) {
  const std::array<double, 3> ref{0.3, 0.6, 0.45};
  ExpectWalkReaches("warped linear hexes", Mesh(CellType::Hex, 3, Warp), GridCell(0, 0, 0), GridCell(3, 2, 1), ref, 4);
  ExpectWalkReaches("sheared (affine) hexes", Mesh(CellType::Hex, 3, Shear), GridCell(5, 4, 3), GridCell(2, 2, 1), ref,
                    4);
  ExpectWalkReaches("distorted hexes", Mesh(CellType::Hex, 3, Distorted), GridCell(1, 0, 0), GridCell(3, 3, 2), ref, 4);
  // Quadratic curved hexes, one Bezier patch each (6 x 5 x 4, u fastest).
  ExpectWalkReaches("quadratic hexes", QuadraticMesh(true), GridCell(0, 0, 0), GridCell(2, 3, 1), ref, 4);
  const std::array<double, 3> wedgeRef{0.2, 0.3, 0.7};
  ExpectWalkReaches("warped wedges", Mesh(CellType::Wedge, 3, Warp), GridCell(0, 0, 0, 2), GridCell(2, 2, 1, 2) + 1,
                    wedgeRef, 4);
  ExpectWalkReaches("curved quadratic wedges", CurvedWedges(), GridCell(0, 0, 0, 2), GridCell(2, 2, 1, 2) + 1,
                    wedgeRef, 4);
  ExpectWalkReaches("sheared wedges", Mesh(CellType::Wedge, 3, Shear), GridCell(4, 1, 2, 2) + 1,
                    GridCell(2, 2, 1, 2), wedgeRef, 3);
}

TEST(VolumeWalkTest, WalksFromHexahedraThroughWedgesIntoTetrahedra) {
  // MixedVolumeMesh: 18 hexes, then 36 wedges, then 108 tets (3 x 3 x 2
  // cubes each); from a hex at x < 1 to a tet above the wedges.
  const Geometry g = MixedVolumeMesh();
  const std::int64_t hexOrigin = 0, firstTet = 18 + 36;
  const std::int64_t tet = firstTet + ((0 * 3 + 1) * 3 + 1) * 6 + 2;  // cube (1, 1, 0) of the tet block
  ExpectWalkReaches("mixed", g, hexOrigin + 2 + 3 * 1 + 9 * 1, tet, {0.2, 0.25, 0.3}, 3);
}

/// The batch on `g` against the reference: points inside, on the cells'
/// faces and edges (most shared by two or more cells), near, mid-range and
/// outside; then the same bits on 1, 2 and 7 threads (buckets of 7 and 32).
void ExpectBatchAnswers(const char* name, const Geometry& g) {
  ReferenceGeometry reference(g);
  QueryMix mix;
  mix.inside = 1500;
  mix.on = 200;
  mix.near = 200;
  mix.mid = 40;
  mix.far = 20;
  QuerySet q = MakeQueries(reference.cells(), g.dimension, reference.size(), mix, 29);
  std::mt19937_64 rng(31);
  for (int i = 0; i < ScaledCount(400); ++i) {
    const RefCell& cell = reference.cells()[rng() % reference.cells().size()].cell;
    const std::array<double, 3> ref = RandomBoundaryRefPoint(cell.type, rng);
    double x[3] = {0, 0, 0};
    RefEvaluate(cell, ref.data(), x);
    q.Add(x, "face");
  }
  RunFamily(name, g, q, [&](const double* p) { return reference.Closest(p); });
  const BuildResult built = Manifold::Build(g);
  ASSERT_TRUE(built.error.empty()) << built.error;
  ExpectSameBitsOnThreads(name, built.manifold, q, {7, 32});
}

TEST(VolumeWalkTest, HexahedraAgainstReference) {
  ExpectBatchAnswers("warped linear hexes", Mesh(CellType::Hex, 3, Warp));
  ExpectBatchAnswers("sheared hexes", Mesh(CellType::Hex, 3, Shear));
  ExpectBatchAnswers("distorted hexes", Mesh(CellType::Hex, 3, Distorted));
  ExpectBatchAnswers("quadratic hexes", QuadraticMesh(true));
}

TEST(VolumeWalkTest, WedgesAndMixedAgainstReference) {
  ExpectBatchAnswers("warped wedges", Mesh(CellType::Wedge, 3, Warp));
  ExpectBatchAnswers("sheared wedges", Mesh(CellType::Wedge, 3, Shear));
  ExpectBatchAnswers("curved quadratic wedges", CurvedWedges());
  ExpectBatchAnswers("mixed hexes, wedges, tets", MixedVolumeMesh());
}

TEST(VolumeWalkTest, PlanarParallelogramsAgainstReference) {
  // Affine quads in the plane take the closed-form inside test too.
  ExpectBatchAnswers("sheared quads 2d", Mesh(CellType::Quad, 2, Shear));
}

}  // namespace
}  // namespace invmap::testing
