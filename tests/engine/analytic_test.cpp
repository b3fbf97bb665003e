// Whole-engine inversion on NURBS shapes with closed-form distances: spheres
// with collapsed poles, tori, circles and annuli in 2D and 3D. The reference
// is the formula; invmap must find the global minimum for every point,
// including the near-ties around centres and axes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>

#include "invmap/invmap.h"
#include "tests/support/family_runner.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

/// Checks every point against the analytic `distance` (all must be found).
void RunAnalytic(const char* name, const Geometry& geometry, const QuerySet& queries,
                 const std::function<double(const double*)>& distance) {
  const CheckSummary summary = RunFamily(name, geometry, queries, [&](const double* p) {
    ReferenceAnswer a;
    a.distance = distance(p);
    return a;
  });
  EXPECT_EQ(summary.found, static_cast<std::int64_t>(queries.size())) << name;
}

/// Adds `count` points center + random direction * U(lo, hi) (dimension dim).
void AddShell(QuerySet* q, const Vec3& center, double lo, double hi, int count, const char* kind, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> radius(lo, hi);
  count = ScaledCount(count);
  for (int i = 0; i < count; ++i) {
    const Vec3 dir = RandomDirection(q->dim, rng);
    const double r = radius(rng);
    const Vec3 p{{center[0] + r * dir[0], center[1] + r * dir[1], center[2] + r * dir[2]}};
    q->Add(p.data(), kind);
  }
}

TEST(AnalyticTest, NurbsSphere) {
  const Vec3 c{{0.3, -0.2, 0.1}};
  const double r = 1.3;
  const Geometry g = NurbsSphere(c, r);
  const double size = GeometrySize(g);
  QueryMix mix;
  mix.on = 5000;
  mix.near = 51000;
  mix.mid = 17000;
  mix.far = 25000;
  QuerySet q = MakeQueries(GeometryCells(g), 3, size, mix, 101);
  std::mt19937_64 rng(102);
  // Near the centre every point of the sphere is almost equally close (about
  // 1 ms a point: the search cannot exclude any part of any cell).
  AddShell(&q, c, 0.0, 0.05 * r, 2000, "centre", rng);
  // Around the poles the net collapses (singular parametrization); these
  // points cost invmap about 9 ms (near) and 2 ms (on the axis) each.
  for (double side : {-1.0, 1.0}) {
    AddShell(&q, {{c[0], c[1], c[2] + side * r}}, 0.0, 0.02 * r, 200, "pole", rng);
    AddShell(&q, {{c[0], c[1], c[2] + side * 3 * r}}, 0.0, 0.5 * r, 200, "pole axis", rng);
  }
  RunAnalytic("sphere", g, q, [&](const double* p) { return SphereDistance(c, r, p); });
}

TEST(AnalyticTest, NurbsSpheresAtTheEndsOfTheSupportedRange) {
  // Coordinates up to 1e100 and extents down to 1e-100 are accepted: squared
  // distances and their tolerances stay normal doubles there. (A sphere of
  // radius 1e155 got a closest point 1e155 off, one of 1e-170 distance 0.)
  std::mt19937_64 rng(103);
  for (const double r : {3e99, 1e95, 1e-95, 2e-99}) {
    const Vec3 c{{0.3 * r, -0.2 * r, 0.1 * r}};
    const Geometry g = NurbsSphere(c, r);
    QuerySet q;
    q.dim = 3;
    AddShell(&q, c, 0.0, 0.5 * r, 300, "inside", rng);
    AddShell(&q, c, 0.5 * r, 1.5 * r, 1000, "near", rng);
    AddShell(&q, c, 1.5 * r, 20 * r, 500, "far", rng);
    char name[64];
    std::snprintf(name, sizeof(name), "sphere of radius %g", r);
    RunAnalytic(name, g, q, [&](const double* p) { return SphereDistance(c, r, p); });
  }
}

/// The surface of the cube c +- h as a mesh of 6 quads or 12 triangles.
Patch CubeSurface(CellType type, const Vec3& c, double h) {
  Patch patch;
  patch.kind = Patch::Kind::Mesh;
  patch.cell = type;
  for (int corner = 0; corner < 8; ++corner) {
    for (int k = 0; k < 3; ++k) patch.points.push_back(c[k] + ((corner >> k) & 1 ? h : -h));
  }
  const std::int64_t faces[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
  for (const auto& f : faces) {
    if (type == CellType::Quad) {
      patch.cells.insert(patch.cells.end(), f, f + 4);
    } else {
      patch.cells.insert(patch.cells.end(), {f[0], f[1], f[2], f[0], f[2], f[3]});
    }
  }
  return patch;
}

/// The outline of the square (c[0], c[1]) +- h in 2D: 4 segments.
Patch SquareOutline(const Vec3& c, double h) {
  Patch patch;
  patch.kind = Patch::Kind::Mesh;
  patch.cell = CellType::Line;
  patch.points = {c[0] - h, c[1] - h, c[0] + h, c[1] - h, c[0] + h, c[1] + h, c[0] - h, c[1] + h};
  patch.cells = {0, 1, 1, 2, 2, 3, 3, 0};
  return patch;
}

/// Distance from p to the box c +- h (solid: 0 inside) or to its surface.
double BoxDistance(int dim, const Vec3& c, double h, const double* p, bool solid) {
  double outside[3] = {0, 0, 0}, deepest = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < dim; ++k) {
    const double q = std::abs(p[k] - c[k]) - h;
    outside[k] = std::max(q, 0.0);
    deepest = std::max(deepest, q);
  }
  if (deepest > 0.0) return std::hypot(outside[0], outside[1], outside[2]);
  return solid ? 0.0 : -deepest;
}

TEST(AnalyticTest, AffineAndBilinearCellsAtTheEndsOfTheSupportedRange) {
  // Triangles, segments and tetrahedra are solved in closed form, whose
  // products of four to six edge lengths overflowed at 1e80 and underflowed
  // at 1e-80 (distances off by up to 20%, a point inside a triangle 1e-90
  // across reported 1e-91 from it); quads and hexes by Newton on their nets.
  std::mt19937_64 rng(107);
  for (const double h : {3e99, 1e95, 1e80, 1e-80, 1e-95, 2e-99}) {
    const Vec3 c{{0.3 * h, -0.2 * h, 0.1 * h}};
    const auto cube = [&](double u, double v, double w) {
      return Vec3{{c[0] + h * (2 * u - 1), c[1] + h * (2 * v - 1), c[2] + h * (2 * w - 1)}};
    };
    struct Case {
      const char* name;
      int dim;
      Patch patch;
      bool solid;
    };
    const Case cases[] = {{"triangles", 3, CubeSurface(CellType::Tri, c, h), false},
                          {"quads", 3, CubeSurface(CellType::Quad, c, h), false},
                          {"tetrahedra", 3, GridMesh(CellType::Tet, 3, 2, 2, 2, cube), true},
                          {"hexahedra", 3, GridMesh(CellType::Hex, 3, 2, 1, 1, cube), true},
                          {"segments", 2, SquareOutline(c, h), false}};
    for (const Case& cs : cases) {
      Geometry g;
      g.dimension = cs.dim;
      g.patches.push_back(cs.patch);
      QuerySet q;
      q.dim = cs.dim;
      const Vec3 centre{{c[0], c[1], cs.dim == 3 ? c[2] : 0.0}};
      AddShell(&q, centre, 0.0, 1.5 * h, 600, "near", rng);
      AddShell(&q, centre, 1.5 * h, 20 * h, 300, "far", rng);
      char name[80];
      std::snprintf(name, sizeof(name), "%s, cube of half-width %g", cs.name, h);
      RunAnalytic(name, g, q, [&](const double* p) { return BoxDistance(cs.dim, c, h, p, cs.solid); });
    }
  }
}

TEST(AnalyticTest, NurbsTorus) {
  const Vec3 c{{-0.1, 0.2, 0.05}};
  const double big = 1.0, small = 0.35;
  const Geometry g = NurbsTorus(c, big, small);
  const double size = GeometrySize(g);
  QueryMix mix;
  mix.on = 5000;
  mix.near = 45000;
  mix.mid = 20000;
  mix.far = 25000;
  QuerySet q = MakeQueries(GeometryCells(g), 3, size, mix, 201);
  std::mt19937_64 rng(202);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // Few axis points: each costs invmap 10 to 500 ms (a whole circle of
  // exact ties that the certified search cannot exclude).
  for (int i = 0; i < ScaledCount(5010); ++i) {
    double p[3];
    if (i % 501 == 0) {
      // The z axis: equidistant from a whole circle of the torus.
      p[0] = c[0] + 1e-7 * (unit(rng) - 0.5);
      p[1] = c[1] + 1e-7 * (unit(rng) - 0.5);
      p[2] = c[2] + 3.0 * (unit(rng) - 0.5);
    } else {
      // Near the core circle: equidistant from a whole circle of the tube.
      const double angle = 6.283185307179586 * unit(rng);
      const Vec3 d = RandomDirection(3, rng);
      const double rho = big + 0.02 * small * d[0];
      p[0] = c[0] + rho * std::cos(angle);
      p[1] = c[1] + rho * std::sin(angle);
      p[2] = c[2] + 0.02 * small * d[2];
    }
    q.Add(p, i % 501 == 0 ? "axis" : "core");
  }
  RunAnalytic("torus", g, q, [&](const double* p) { return TorusDistance(c, big, small, p); });
}

TEST(AnalyticTest, NurbsCircles) {
  for (int dim : {2, 3}) {
    SCOPED_TRACE("dimension " + std::to_string(dim));
    const Frame frame = dim == 3 ? TiltedFrame({{0.2, 0.1, -0.3}}) : Frame{{{0.2, 0.1, 0}}, {{1, 0, 0}}, {{0, 1, 0}}};
    const double r = 0.8;
    const Geometry g = NurbsCircle(dim, frame, r);
    QueryMix mix;
    mix.on = 3000;
    mix.near = 22000;
    mix.mid = 8000;
    mix.far = 12000;
    QuerySet q = MakeQueries(GeometryCells(g), dim, GeometrySize(g), mix, 301 + dim);
    std::mt19937_64 rng(303 + dim);
    // The centre (2D) or the axis (3D) is equidistant from the whole circle.
    AddShell(&q, frame.origin, 0.0, 0.03 * r, 4000, "centre", rng);
    if (dim == 3) {
      const Vec3 axis{{frame.e1[1] * frame.e2[2] - frame.e1[2] * frame.e2[1],
                       frame.e1[2] * frame.e2[0] - frame.e1[0] * frame.e2[2],
                       frame.e1[0] * frame.e2[1] - frame.e1[1] * frame.e2[0]}};
      std::uniform_real_distribution<double> height(-2.0, 2.0);
      for (int i = 0; i < ScaledCount(3000); ++i) {
        const double h = height(rng);
        const Vec3 p{{frame.origin[0] + h * axis[0], frame.origin[1] + h * axis[1], frame.origin[2] + h * axis[2]}};
        q.Add(p.data(), "axis");
      }
    }
    RunAnalytic(dim == 2 ? "circle 2D" : "circle 3D", g, q,
                [&](const double* p) { return CircleDistance(dim, frame, r, p); });
  }
}

TEST(AnalyticTest, NurbsAnnuli) {
  for (int dim : {2, 3}) {
    SCOPED_TRACE("dimension " + std::to_string(dim));
    const Frame frame = dim == 3 ? TiltedFrame({{-0.4, 0.3, 0.2}}) : Frame{{{-0.4, 0.3, 0}}, {{1, 0, 0}}, {{0, 1, 0}}};
    const double r1 = 0.5, r2 = 1.1;
    const Geometry g = NurbsAnnulus(dim, frame, r1, r2);
    QueryMix mix;
    mix.on = 3000;
    mix.near = 20000;
    mix.mid = 10000;
    mix.far = 12000;
    mix.inside = dim == 2 ? 5000 : 0;  // a 2D annulus is a full-rank patch
    QuerySet q = MakeQueries(GeometryCells(g), dim, GeometrySize(g), mix, 401 + dim);
    std::mt19937_64 rng(403 + dim);
    AddShell(&q, frame.origin, 0.0, 0.03 * r1, 3000, "centre", rng);
    RunAnalytic(dim == 2 ? "annulus 2D" : "annulus 3D", g, q,
                [&](const double* p) { return AnnulusDistance(dim, frame, r1, r2, p); });
  }
}

}  // namespace
}  // namespace invmap::testing
