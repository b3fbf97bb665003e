// Where the walk through a volume mesh starts (engine/walk_start_grid.h),
// on meshes where a bad start would show: a tunnel through the mesh and a
// notch cut from its corner (holes and a concave boundary, so grid cells lie
// in empty space and a straight walk from them leaves the mesh), warped
// (curved trilinear) hexahedra, and parts apart from each other. Points on
// a lattice finer than the grid (so that every grid cell gets some), over a
// box larger than the mesh's, are checked against independent references:
// a brute force over every tetrahedron (the barycentric coordinates, from
// the tests' own solve) for the cell and preimage of every point inside,
// and the culled global reference (tests/support/closest_reference.h) for
// every point; then the same bits on 1, 2 and 7 threads.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>

#include "engine/search_index.h"
#include "invmap/invmap.h"
#include "tests/support/closest_reference.h"
#include "tests/support/family_runner.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

using CubeFilter = std::function<bool(int, int, int)>;

/// GridMesh(type, 3, n, n, n, f) without the cubes `keep` rejects (cube
/// (i, j, k) of the n^3 grid; a tetrahedron mesh has 6 cells a cube, a
/// wedge mesh 2).
Patch CarvedMesh(CellType type, int n, const std::function<Vec3(double, double, double)>& f, const CubeFilter& keep) {
  Patch grid = GridMesh(type, 3, n, n, n, f);
  const int vertices = type == CellType::Hex ? 8 : type == CellType::Wedge ? 6 : 4;
  const int perCube = type == CellType::Hex ? 1 : type == CellType::Wedge ? 2 : 6;
  std::vector<std::int64_t> kept;
  const std::size_t cells = grid.cells.size() / vertices;
  for (std::size_t c = 0; c < cells; ++c) {
    const int cube = static_cast<int>(c / perCube);
    if (!keep(cube % n, (cube / n) % n, cube / (n * n))) continue;
    kept.insert(kept.end(), grid.cells.begin() + c * vertices, grid.cells.begin() + (c + 1) * vertices);
  }
  grid.cells = kept;
  return grid;
}

/// The unit cube, sheared and with every inner vertex moved by up to a
/// fifth of a cube of 8: tetrahedra of many shapes, still conforming.
Vec3 JitteredShear(double a, double b, double c) {
  Vec3 x{a + 0.2 * b + 0.1 * c, 0.1 * a + 0.9 * b - 0.05 * c, -0.1 * a + 0.15 * b + 1.1 * c};
  const bool inner = a > 0 && a < 1 && b > 0 && b < 1 && c > 0 && c < 1;
  if (inner) {
    x[0] += 0.2 / 8 * std::sin(37 * a + 11 * b + 5 * c);
    x[1] += 0.2 / 8 * std::sin(13 * a + 29 * b + 7 * c);
    x[2] += 0.2 / 8 * std::sin(17 * a + 3 * b + 31 * c);
  }
  return x;
}

Vec3 Warp(double a, double b, double c) {
  return Vec3{a + 0.15 * b * b + 0.05 * c, b + 0.1 * std::sin(2 * a) + 0.05 * c * a, c + 0.1 * a * b};
}

/// A tunnel along z through cubes 2 <= i < 5, 3 <= j < 5 and a notch at
/// i, j >= 6 (of 8).
bool TunnelAndNotch(int i, int j, int) { return !(i >= 2 && i < 5 && j >= 3 && j < 5) && !(i >= 6 && j >= 6); }

Patch Shifted(Patch patch, const Vec3& by) {
  for (std::size_t i = 0; i < patch.points.size(); ++i) patch.points[i] += by[i % 3];
  return patch;
}

/// Points of a lattice of `perAxis`^3 over the geometry's box widened by
/// 15% on each side, offset by an irrational fraction of a step (so that
/// some land on faces only by the mesh's own shape).
QuerySet LatticePoints(const Geometry& g, int perAxis) {
  const double inf = std::numeric_limits<double>::infinity();
  double lo[3] = {inf, inf, inf}, hi[3] = {-inf, -inf, -inf};
  for (const Patch& patch : g.patches) {
    for (std::size_t i = 0; i < patch.points.size(); ++i) {
      lo[i % 3] = std::min(lo[i % 3], patch.points[i]);
      hi[i % 3] = std::max(hi[i % 3], patch.points[i]);
    }
  }
  QuerySet q;
  q.dim = 3;
  for (int z = 0; z < perAxis; ++z) {
    for (int y = 0; y < perAxis; ++y) {
      for (int x = 0; x < perAxis; ++x) {
        const int at[3] = {x, y, z};
        double p[3];
        for (int k = 0; k < 3; ++k) {
          const double width = 1.3 * (hi[k] - lo[k]);
          p[k] = lo[k] - 0.15 * (hi[k] - lo[k]) + width * (at[k] + 0.5 * std::sqrt(2.0) - 0.2) / perAxis;
        }
        q.Add(p, "lattice");
      }
    }
  }
  return q;
}

/// The tests' own barycentric coordinates of p in the tetrahedron v[0..3]
/// (Cramer's rule); false for a flat one.
bool Barycentric(const double* const* v, const double* p, double* lambda) {
  double e[3][3], w[3];
  for (int k = 0; k < 3; ++k) {
    for (int i = 0; i < 3; ++i) e[k][i] = v[i + 1][k] - v[0][k];
    w[k] = p[k] - v[0][k];
  }
  const auto det3 = [](const double m[3][3]) {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  };
  const double det = det3(e);
  if (det == 0.0) return false;
  for (int i = 0; i < 3; ++i) {
    double m[3][3];
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) m[r][c] = c == i ? w[r] : e[r][c];
    }
    lambda[i + 1] = det3(m) / det;
  }
  lambda[0] = 1.0 - lambda[1] - lambda[2] - lambda[3];
  return true;
}

/// The least barycentric coordinate of p over the linear tetrahedra of the
/// Mesh patches of `g` that hold it best (a brute force over all of them);
/// -infinity when there is none.
double DeepestInTetrahedra(const Geometry& g, const double* p) {
  double deepest = -std::numeric_limits<double>::infinity();
  for (const Patch& patch : g.patches) {
    if (patch.kind != Patch::Kind::Mesh || patch.cell != CellType::Tet) continue;
    for (std::size_t c = 0; c + 4 <= patch.cells.size(); c += 4) {
      const double* v[4];
      for (int k = 0; k < 4; ++k) v[k] = &patch.points[3 * static_cast<std::size_t>(patch.cells[c + k])];
      double lambda[4];
      if (Barycentric(v, p, lambda)) deepest = std::max(deepest, std::min({lambda[0], lambda[1], lambda[2], lambda[3]}));
    }
  }
  return deepest;
}

/// A point some tetrahedron holds (DeepestInTetrahedra at least -1e-9) is
/// found at distance 0 in a tetrahedron that holds it to 1e-9, with the
/// parameters its barycentric coordinates.
void ExpectTetrahedronAnswer(const char* name, const Geometry& g, const double* p, const Results& results,
                             std::size_t i) {
  ASSERT_EQ(results.status[i], Status::Found) << name << ": point " << i;
  EXPECT_EQ(results.distance[i], 0.0) << name << ": point " << i;
  const Patch& patch = g.patches[static_cast<std::size_t>(results.patch[i])];
  ASSERT_EQ(patch.cell, CellType::Tet) << name << ": point " << i;
  const std::size_t c = 4 * static_cast<std::size_t>(results.cell[i]);
  const double* v[4];
  for (int k = 0; k < 4; ++k) v[k] = &patch.points[3 * static_cast<std::size_t>(patch.cells[c + k])];
  double lambda[4];
  ASSERT_TRUE(Barycentric(v, p, lambda)) << name;
  EXPECT_GE(std::min({lambda[0], lambda[1], lambda[2], lambda[3]}), -1e-9) << name << ": point " << i;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(results.params[3 * i + k], lambda[k + 1], 1e-9) << name << ": point " << i;
}

/// The whole check of one geometry: every point some tetrahedron holds
/// against the brute force over the tetrahedra, every `referenceEvery`-th
/// other point against the global reference (the closest point, for points
/// in the holes, the notch, between the parts and beyond the mesh: the
/// reference is slow off the mesh), then the same bits on any thread count
/// for every point. At least `minInside` points lie inside tetrahedra by a
/// margin of 1e-6.
void ExpectLatticeAnswers(const char* name, const Geometry& g, int perAxis, int referenceEvery, int minInside) {
  const QuerySet q = LatticePoints(g, perAxis);
  std::vector<double> deepest(q.size());
  for (std::size_t i = 0; i < q.size(); ++i) deepest[i] = DeepestInTetrahedra(g, q.point(i));
  ReferenceGeometry reference(g);
  const BuildResult built = Manifold::Build(g);
  ASSERT_TRUE(built.error.empty()) << built.error;
  InversionOptions options;
  options.threads = 1;
  std::string error;
  const Results results = InvertQueries(built.manifold, q, options, &error);
  ASSERT_TRUE(error.empty()) << error;
  int inside = 0;
  QuerySet outside;
  for (std::size_t i = 0; i < q.size(); ++i) {
    if (deepest[i] >= -1e-9) {
      ExpectTetrahedronAnswer(name, g, q.point(i), results, i);
      inside += deepest[i] >= 1e-6;
    } else if (i % referenceEvery == 0) {
      outside.Add(q.point(i), "not in a tetrahedron");
    }
  }
  EXPECT_GE(inside, minInside) << name;
  RunFamily(name, g, outside, [&](const double* p) { return reference.Closest(p); });
  ExpectSameBitsOnThreads(name, built.manifold, q, {7, 32});
}

TEST(WalkStartGridTest, TetrahedraWithTunnelAndNotch) {
  Geometry g;
  g.dimension = 3;
  g.patches.push_back(CarvedMesh(CellType::Tet, 8, JitteredShear, TunnelAndNotch));
  ExpectLatticeAnswers("tets, tunnel and notch", g, 26, 4, 3000);
}

TEST(WalkStartGridTest, WarpedHexahedraWithTunnelAndNotch) {
  Geometry g;
  g.dimension = 3;
  g.patches.push_back(CarvedMesh(CellType::Hex, 8, Warp, TunnelAndNotch));
  ExpectLatticeAnswers("warped hexes, tunnel and notch", g, 24, 1, 0);
}

/// A shear of the unit cube: hexahedra stay parallelepipeds, which the walk
/// steps through by their frames (engine/hex_frames.h).
Vec3 Shear(double a, double b, double c) {
  return Vec3{a + 0.2 * b + 0.1 * c, 0.1 * a + 0.9 * b - 0.05 * c, -0.1 * a + 0.15 * b + 1.1 * c};
}

TEST(WalkStartGridTest, ShearedHexahedraWithTunnelAndNotch) {
  Geometry g;
  g.dimension = 3;
  g.patches.push_back(CarvedMesh(CellType::Hex, 8, Shear, TunnelAndNotch));
  ASSERT_FALSE(engine::SearchIndex::Build(g, 1).cells().faceAdjacency().frames().empty());
  ExpectLatticeAnswers("sheared hexes, tunnel and notch", g, 24, 1, 0);
}

TEST(WalkStartGridTest, ShearedHexahedraApartFromTetrahedra) {
  // Most cells parallelepipeds (so they have frames), the rest tetrahedra
  // and warped hexahedra (which have none) in parts of their own.
  Geometry g;
  g.dimension = 3;
  const CubeFilter all = [](int, int, int) { return true; };
  g.patches.push_back(CarvedMesh(CellType::Hex, 8, Shear, TunnelAndNotch));
  g.patches.push_back(Shifted(CarvedMesh(CellType::Tet, 2, JitteredShear, all), {1.6, 0.0, 0.0}));
  g.patches.push_back(Shifted(CarvedMesh(CellType::Hex, 3, Warp, all), {0.0, 0.0, 1.6}));
  ASSERT_FALSE(engine::SearchIndex::Build(g, 1).cells().faceAdjacency().frames().empty());
  ExpectLatticeAnswers("sheared hexes apart from tets and warped hexes", g, 26, 2, 200);
}

TEST(WalkStartGridTest, PartsApart) {
  // Two tetrahedron blocks and a hexahedron block, apart, with gaps wider
  // than a block: most grid cells are empty, and a walk between parts
  // finds no face to cross.
  Geometry g;
  g.dimension = 3;
  const CubeFilter all = [](int, int, int) { return true; };
  g.patches.push_back(CarvedMesh(CellType::Tet, 4, JitteredShear, all));
  g.patches.push_back(Shifted(CarvedMesh(CellType::Hex, 4, Warp, all), {2.5, 0.0, 0.0}));
  g.patches.push_back(Shifted(CarvedMesh(CellType::Tet, 3, JitteredShear, TunnelAndNotch), {0.3, 0.2, 3.0}));
  ExpectLatticeAnswers("parts apart", g, 32, 4, 1000);
}

TEST(WalkStartGridTest, StartsNearThePoint) {
  // The grid's start for a point of the mesh lies within about a cell of
  // it (the walk then crosses a face or two); one of a point beyond the
  // mesh, NaN or infinite, is a cell of the mesh or none.
  Geometry g;
  g.dimension = 3;
  g.patches.push_back(CarvedMesh(CellType::Tet, 8, JitteredShear, TunnelAndNotch));
  const engine::SearchIndex index = engine::SearchIndex::Build(g, 1);
  const engine::CellStore& store = index.cells();
  const engine::WalkStartGrid& grid = store.faceAdjacency().startGrid();
  ASSERT_FALSE(grid.empty());
  const QuerySet q = LatticePoints(g, 30);
  int inside = 0;
  for (std::size_t i = 0; i < q.size(); ++i) {
    const std::int64_t start = grid.StartCell(q.point(i));
    ASSERT_GE(start, -1);
    ASSERT_LT(start, store.size());
    if (DeepestInTetrahedra(g, q.point(i)) < 0.0) continue;
    ++inside;
    ASSERT_GE(start, 0) << "point " << i;
    // Within a cube's width and a half of the start cell's box (a cube of
    // the jittered shear is at most about 1.5 / 8 wide).
    const kernels::CellSolver& solver = store.solver(start);
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double x = q.point(i)[k];
      const double out = std::max({solver.boxLo()[k] - x, x - solver.boxHi()[k], 0.0});
      d2 += out * out;
    }
    EXPECT_LE(std::sqrt(d2), 1.5 * 1.5 / 8) << "point " << i;
  }
  EXPECT_GE(inside, 5000);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const Vec3& p : {Vec3{nan, 0.5, 0.5}, Vec3{inf, -inf, 0.5}, Vec3{1e300, -1e300, nan}, Vec3{-5, 7, 2}}) {
    const std::int64_t start = grid.StartCell(p.data());
    EXPECT_GE(start, -1);
    EXPECT_LT(start, store.size());
  }
}

}  // namespace
}  // namespace invmap::testing
