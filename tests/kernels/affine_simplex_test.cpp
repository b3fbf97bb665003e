// Closest points on affine triangles (kernels/affine_simplex.h and its lanes)
// against answers known by construction: a point X of the triangle (inside,
// on an edge, at a vertex) moved along a direction of the triangle's normal
// cone at X has X as its closest point, at the distance moved. The triangles
// run from well shaped to slivers whose third vertex lies 1e-12 of their
// length off the opposite edge (caps) and needles with a short edge, turned
// and moved far from the origin. The construction is carried out in
// quadruple precision (__float128) from the triangle's double vertices (the
// triangle the solver sees), and only the query point is rounded to double:
// a sliver's normal and the directions across its edges are as ill
// conditioned as its answers (long double moved the constructed distance
// of a point beside a sliver of height 1e-7 by 1e-13 of its length).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "kernels/affine_simplex.h"
#include "kernels/affine_simplex_lanes.h"

namespace {

using invmap::kernels::ClosestPointOnSimplex;
using invmap::kernels::ClosestPointsOnSimplexLanes;
using invmap::kernels::kSimplexLaneChunk;

using Real = __float128;
using Vec = std::array<Real, 3>;

/// Square root to quadruple precision: Newton from the double root.
Real Sqrt(Real x) {
  if (!(x > 0)) return 0;
  Real r = std::sqrt(static_cast<double>(x));
  for (int i = 0; i < 3; ++i) r = 0.5 * (r + x / r);
  return r;
}

Vec Sub(const Vec& u, const Vec& v) { return {u[0] - v[0], u[1] - v[1], u[2] - v[2]}; }
Vec Add(const Vec& u, const Vec& v) { return {u[0] + v[0], u[1] + v[1], u[2] + v[2]}; }
Vec Scale(Real s, const Vec& v) { return {s * v[0], s * v[1], s * v[2]}; }
Real Dot(const Vec& u, const Vec& v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; }
Vec Cross(const Vec& u, const Vec& v) {
  return {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
}
Vec Unit(const Vec& v) { return Scale(Real(1) / Sqrt(Dot(v, v)), v); }

/// A random unit vector.
Vec RandomDirection(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  return Unit({normal(rng), normal(rng), normal(rng)});
}

/// A triangle with double vertices, of length about `size` near `center`.
struct Triangle {
  std::array<std::array<double, 3>, 3> v;
  Vec Vertex(int i) const { return {v[i][0], v[i][1], v[i][2]}; }
};

/// Shapes: well shaped, a cap (the third vertex `height` x length off the
/// opposite edge, somewhere along it) or a needle (an edge `height` x length
/// long, the third vertex far away). `planar`: z = 0.
Triangle RandomTriangle(std::mt19937_64& rng, int shape, double height, double size, double center, bool planar) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Vec e1 = RandomDirection(rng), up = RandomDirection(rng);
  if (planar) {
    e1[2] = Real(0);
    e1 = Unit(e1);
    up = {-e1[1], e1[0], Real(0)};
  }
  // The in-plane direction perpendicular to e1.
  const Vec across = Unit(Sub(up, Scale(Dot(up, e1), e1)));
  const Vec a = {center + size * unit(rng), center + size * unit(rng), planar ? 0.0 : center + size * unit(rng)};
  const Vec b = Add(a, Scale(size, e1));
  Vec c;
  if (shape == 0) {
    c = Add(Add(a, Scale(size * unit(rng), e1)), Scale(size * (0.3 + unit(rng)), across));
  } else if (shape == 1) {
    c = Add(Add(a, Scale(size * (0.05 + 0.9 * unit(rng)), e1)), Scale(size * height, across));
  } else {
    c = Add(b, Scale(size * height, Unit(Add(across, Scale(unit(rng) - 0.5, e1)))));
  }
  Triangle t;
  const Vec corners[3] = {a, b, c};
  // Any vertex may come first: the solver's formulas are not symmetric.
  const int first = static_cast<int>(rng() % 3);
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) t.v[i][k] = static_cast<double>(corners[(first + i) % 3][k]);
  }
  return t;
}

/// A query point with its distance to the triangle known by construction.
struct Query {
  std::array<double, 3> p;
  Real distance;
  std::string where;
};

/// Moves X (a point of the triangle) by `height` along the normal and by
/// `out` along `outward` (an in-plane direction of the normal cone at X).
Query MakeQuery(const Vec& x, const Vec& normal, const Vec& outward, Real height, Real out,
                const std::string& where) {
  const Vec p = Add(x, Add(Scale(height, normal), Scale(out, outward)));
  Query q;
  for (int k = 0; k < 3; ++k) q.p[k] = static_cast<double>(p[k]);
  // The rounding of p to double moves it by at most half an ulp per
  // coordinate; the tolerance of the comparison covers that.
  q.distance = Sqrt(height * height + out * out);
  q.where = where;
  return q;
}

/// Points whose closest point on `t` is inside it, on each edge and at each
/// vertex, at heights from 0 (on the triangle or its plane) to its size.
std::vector<Query> QueriesFor(const Triangle& t, std::mt19937_64& rng, double size, bool planar) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Vec v[3] = {t.Vertex(0), t.Vertex(1), t.Vertex(2)};
  std::vector<Query> queries;
  // Vertices that rounding made collinear have no normal cone to follow.
  const Vec cross = Cross(Sub(v[1], v[0]), Sub(v[2], v[0]));
  if (!(Dot(cross, cross) > 0)) return queries;
  const Vec normal = planar ? Vec{0, 0, 0} : Unit(cross);
  for (int repeat = 0; repeat < 4; ++repeat) {
    const Real height = planar || repeat == 0 ? Real(0) : Real((repeat == 1 ? 1e-9 : unit(rng)) * size);
    // Inside: random barycentric coordinates.
    Real w1 = unit(rng), w2 = unit(rng);
    if (w1 + w2 > 1) {
      w1 = 1 - w1;
      w2 = 1 - w2;
    }
    const Vec inside = Add(v[0], Add(Scale(w1, Sub(v[1], v[0])), Scale(w2, Sub(v[2], v[0]))));
    queries.push_back(MakeQuery(inside, normal, normal, height, Real(0), "inside"));
    for (int e = 0; e < 3; ++e) {
      const Vec& from = v[e];
      const Vec& to = v[(e + 1) % 3];
      const Vec& opposite = v[(e + 2) % 3];
      const Vec along = Unit(Sub(to, from));
      // Outward in the plane: away from the opposite vertex, across the edge.
      const Vec toOpposite = Sub(opposite, from);
      const Vec outward = Unit(Scale(-Real(1), Sub(toOpposite, Scale(Dot(toOpposite, along), along))));
      const Vec onEdge = Add(from, Scale(Real(0.05) + Real(0.9) * unit(rng), Sub(to, from)));
      const Real out = repeat == 0 ? Real(0) : Real(unit(rng) * size);
      queries.push_back(MakeQuery(onEdge, normal, outward, height, out, "edge " + std::to_string(e)));
      // At vertex `from`: away from both its edges.
      const Vec corner = Unit(Scale(-Real(1), Add(Unit(Sub(to, from)), Unit(Sub(opposite, from)))));
      queries.push_back(MakeQuery(from, normal, corner, height, out, "vertex " + std::to_string(e)));
    }
  }
  return queries;
}

/// Checks one answer: the distance against the construction's, the closest
/// point against the reference coordinates, and both against the distance.
void ExpectAnswer(const Triangle& t, const Query& q, double s, double r, double dist2, const double* closest,
                  double tolerance, const std::string& label) {
  SCOPED_TRACE(label + " " + q.where);
  EXPECT_NEAR(std::sqrt(dist2), static_cast<double>(q.distance), tolerance);
  EXPECT_GE(s, 0.0);
  EXPECT_GE(r, 0.0);
  EXPECT_LE(s + r, 1.0 + 1e-15);
  if (closest == nullptr) return;
  Real d2 = 0;
  for (int k = 0; k < 3; ++k) {
    const Real x = t.v[0][k] + s * (t.v[1][k] - t.v[0][k]) + r * (t.v[2][k] - t.v[0][k]);
    EXPECT_NEAR(closest[k], static_cast<double>(x), tolerance) << "coordinate " << k;
    d2 += (Real(closest[k]) - q.p[k]) * (Real(closest[k]) - q.p[k]);
  }
  EXPECT_NEAR(static_cast<double>(Sqrt(d2)), std::sqrt(dist2), tolerance);
}

struct Case {
  int shape;
  double height;
  double size;
  double center;
  bool planar;
};

std::vector<Case> Cases() {
  std::vector<Case> cases;
  for (const bool planar : {false, true}) {
    for (const double center : {0.0, 1e6}) {
      for (const double size : {1.0, 1e-4}) {
        cases.push_back({0, 0.0, size, center, planar});
        for (const double height : {1e-2, 1e-5, 1e-7, 1e-9, 1e-12}) {
          cases.push_back({1, height, size, center, planar});
          cases.push_back({2, height, size, center, planar});
        }
      }
    }
  }
  return cases;
}

std::string Describe(const Case& c) {
  static const char* kShapes[] = {"well shaped", "cap", "needle"};
  char text[128];
  std::snprintf(text, sizeof text, "%s height %g size %g at %g%s", kShapes[c.shape], c.height, c.size, c.center,
                c.planar ? " (2D)" : "");
  return text;
}

/// Rounding of the construction and the solver: a few units in the last
/// place of the coordinates (the query point's own rounding included).
double Tolerance(const Case& c) { return 64 * 2.220446e-16 * (std::abs(c.center) + 2 * c.size); }

/// Calls check(c, triangle, vertices, ambient dimension, queries) for
/// `trials` random triangles of every case that rounding left a triangle.
template <typename Check>
void ForEachTriangle(std::uint64_t seed, int trials, const Check& check) {
  std::mt19937_64 rng(seed);
  for (const Case& c : Cases()) {
    for (int trial = 0; trial < trials; ++trial) {
      const Triangle t = RandomTriangle(rng, c.shape, c.height, c.size, c.center, c.planar);
      const double* v[3] = {t.v[0].data(), t.v[1].data(), t.v[2].data()};
      const std::vector<Query> queries = QueriesFor(t, rng, c.size, c.planar);
      if (!queries.empty()) check(c, t, v, c.planar ? 2 : 3, queries);
    }
  }
}

TEST(ClosestPointOnSimplex, TrianglesFromWellShapedToSlivers) {
  ForEachTriangle(20261125, 20, [](const Case& c, const Triangle& t, const double* const* v, int ambient,
                                   const std::vector<Query>& queries) {
    for (const Query& q : queries) {
      double ref[3], closest[3] = {0, 0, 0};
      bool onBoundary = false;
      const double d2 = ClosestPointOnSimplex(2, ambient, v, q.p.data(), ref, closest, &onBoundary);
      ExpectAnswer(t, q, ref[0], ref[1], d2, closest, Tolerance(c), Describe(c));
    }
  });
}

TEST(ClosestPointsOnSimplexLanes, TrianglesFromWellShapedToSlivers) {
  ForEachTriangle(7, 10, [](const Case& c, const Triangle& t, const double* const* v, int ambient,
                            const std::vector<Query>& queries) {
    // More lanes than one chunk, so the chunking is exercised as well.
    std::vector<Query> lanes;
    while (static_cast<int>(lanes.size()) <= kSimplexLaneChunk) lanes.insert(lanes.end(), queries.begin(), queries.end());
    const int n = static_cast<int>(lanes.size());
    std::vector<double> coord[3], ref[2], dist2(n);
    for (auto& axis : coord) axis.resize(n);
    for (auto& axis : ref) axis.resize(n);
    std::unique_ptr<bool[]> onBoundary(new bool[n]);
    for (int l = 0; l < n; ++l)
      for (int k = 0; k < 3; ++k) coord[k][l] = lanes[l].p[k];
    const double* const coords[3] = {coord[0].data(), coord[1].data(), coord[2].data()};
    double* const refs[3] = {ref[0].data(), ref[1].data(), nullptr};
    ClosestPointsOnSimplexLanes(2, ambient, v, coords, n, refs, dist2.data(), onBoundary.get());
    for (int l = 0; l < n; ++l) {
      ExpectAnswer(t, lanes[l], ref[0][l], ref[1][l], dist2[l], nullptr, Tolerance(c), Describe(c));
    }
  });
}

}  // namespace
