// Tests of the independent reference in tests/support/reference_cell.h: the
// solver tests are only as good as the reference they compare against, so
// the reference is checked here against closed-form geometry.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "tests/support/reference_cell.h"

namespace invmap::testing {
namespace {

using kernels::CellType;
using Vec3 = std::array<double, 3>;

constexpr CellType kAllTypes[] = {CellType::Line, CellType::Tri, CellType::Quad,
                                  CellType::Tet,  CellType::Hex, CellType::Wedge};

Vec3 Sub(const Vec3& a, const Vec3& b) { return {{a[0] - b[0], a[1] - b[1], a[2] - b[2]}}; }
Vec3 Add(const Vec3& a, const Vec3& b) { return {{a[0] + b[0], a[1] + b[1], a[2] + b[2]}}; }
Vec3 Scale(const Vec3& a, double s) { return {{a[0] * s, a[1] * s, a[2] * s}}; }
double Dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double Norm(const Vec3& a) { return std::sqrt(Dot(a, a)); }

/// Closest point of triangle abc to p (Ericson, Real-Time Collision
/// Detection, 5.1.5): Voronoi regions of vertices, edges, then the face.
Vec3 ClosestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = Sub(b, a), ac = Sub(c, a), ap = Sub(p, a);
  const double d1 = Dot(ab, ap), d2 = Dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = Sub(p, b);
  const double d3 = Dot(ab, bp), d4 = Dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return Add(a, Scale(ab, d1 / (d1 - d3)));
  const Vec3 cp = Sub(p, c);
  const double d5 = Dot(ab, cp), d6 = Dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return Add(a, Scale(ac, d2 / (d2 - d6)));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return Add(b, Scale(Sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6))));
  const double denom = 1.0 / (va + vb + vc);
  return Add(a, Add(Scale(ab, vb * denom), Scale(ac, vc * denom)));
}

double DistanceToTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  return Norm(Sub(p, ClosestOnTriangle(p, a, b, c)));
}

double DistanceToSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = Sub(b, a);
  const double t = std::clamp(Dot(Sub(p, a), ab) / Dot(ab, ab), 0.0, 1.0);
  return Norm(Sub(p, Add(a, Scale(ab, t))));
}

/// Solves the 3x3 system m x = r by Cramer's rule.
Vec3 Solve3(const double m[3][3], const Vec3& r) {
  auto det = [](const double a[3][3]) {
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  };
  const double d = det(m);
  Vec3 x{};
  for (int c = 0; c < 3; ++c) {
    double t[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) t[i][j] = j == c ? r[i] : m[i][j];
    x[c] = det(t) / d;
  }
  return x;
}

/// Random matrix a (ambientDim x paramDim, row-major) of an affine map that
/// is far from singular, and a random offset b.
void RandomAffine(int ad, int pd, std::mt19937_64& rng, double* a, double* b) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < ad * pd; ++i) a[i] = u(rng);
  for (int k = 0; k < ad && k < pd; ++k) a[k * pd + k] += 2.0;  // diagonally dominant
  for (int k = 0; k < ad; ++k) b[k] = 3.0 * u(rng);
}

Vec3 Eval(const RefCell& cell, const Vec3& ref) {
  Vec3 x{{0, 0, 0}};
  RefEvaluate(cell, ref.data(), x.data());
  return x;
}

// ---------------------------------------------------------------------------
// Evaluation.

TEST(ReferenceEvaluate, ReproducesAffineMaps) {
  std::mt19937_64 rng(11);
  for (CellType type : kAllTypes) {
    const int pd = ParamDimOf(type);
    for (int ad = std::max(pd, 2); ad <= 3; ++ad) {
      for (int degree = 1; degree <= 6; ++degree) {
        double a[9], b[3];
        RandomAffine(ad, pd, rng, a, b);
        std::array<int, 3> degrees{{degree, std::max(1, degree - 1), degree + 1 > 6 ? 2 : degree + 1}};
        RefCell cell = AffineCell(type, degrees, ad, a, b);
        SCOPED_TRACE(Describe(cell));
        // Equal weights must give the polynomial map back.
        RefCell weighted = cell;
        weighted.weights.assign(cell.numControlPoints(), 1.7);
        for (int trial = 0; trial < 20; ++trial) {
          const Vec3 ref = RandomRefPoint(type, rng);
          for (const RefCell* c : {&cell, &weighted}) {
            RefJet jet;
            RefEvaluateJet(*c, ref.data(), 2, &jet);
            const Vec3 x = Eval(*c, ref);
            for (int k = 0; k < ad; ++k) {
              double expect = b[k];
              for (int i = 0; i < pd; ++i) expect += a[k * pd + i] * ref[i];
              EXPECT_NEAR(x[k], expect, 1e-13);
              EXPECT_NEAR(jet.x[k], expect, 1e-13);
              for (int i = 0; i < pd; ++i) {
                EXPECT_NEAR(jet.d1[k][i], a[k * pd + i], 1e-11);
                for (int j = 0; j < pd; ++j) EXPECT_NEAR(jet.d2[k][i][j], 0.0, 1e-9);
              }
            }
          }
        }
      }
    }
  }
}

TEST(ReferenceEvaluate, InterpolatesCornerControlPoints) {
  std::mt19937_64 rng(12);
  for (CellType type : kAllTypes) {
    const int pd = ParamDimOf(type);
    for (int degree = 1; degree <= 4; ++degree) {
      for (bool rational : {false, true}) {
        const RefCell cell = RandomCurvedCell(type, degree, rational, 3, rng);
        SCOPED_TRACE(Describe(cell));
        const auto locs = ControlPointRefLocations(type, cell.degrees);
        int corners = 0;
        for (size_t c = 0; c < locs.size(); ++c) {
          // A control point is a corner when its location is a vertex of
          // the domain: every coordinate 0 or 1 (simplex vertices included).
          bool corner = true;
          for (int i = 0; i < pd; ++i) corner = corner && (locs[c][i] == 0.0 || locs[c][i] == 1.0);
          if (!corner) continue;
          ++corners;
          const Vec3 x = Eval(cell, locs[c]);
          for (int k = 0; k < 3; ++k) EXPECT_NEAR(x[k], cell.points[3 * c + k], 1e-14 * cell.size());
        }
        const int expected[] = {2, 3, 4, 4, 8, 6};
        EXPECT_EQ(corners, expected[static_cast<int>(type)]);
      }
    }
  }
}

/// Simplex de Casteljau: repeated convex combination of neighbouring control
/// points, a second algorithm for the same polynomial.
Vec3 DeCasteljauSimplex(int dim, int degree, const std::vector<Vec3>& net, const double* s) {
  std::map<std::array<int, 4>, Vec3> level;
  std::vector<std::array<int, 4>> order;
  auto indices = [&](int p) {
    std::vector<std::array<int, 4>> out;
    for (int a3 = 0; a3 <= (dim >= 3 ? p : 0); ++a3)
      for (int a2 = 0; a2 + a3 <= (dim >= 2 ? p : 0); ++a2)
        for (int a1 = 0; a1 + a2 + a3 <= p; ++a1) out.push_back({{p - a1 - a2 - a3, a1, a2, a3}});
    return out;
  };
  const auto top = indices(degree);
  for (size_t i = 0; i < top.size(); ++i) level[top[i]] = net[i];
  double l[4] = {1.0, 0, 0, 0};
  for (int k = 0; k < dim; ++k) {
    l[k + 1] = s[k];
    l[0] -= s[k];
  }
  for (int p = degree - 1; p >= 0; --p) {
    std::map<std::array<int, 4>, Vec3> next;
    for (const auto& a : indices(p)) {
      Vec3 v{{0, 0, 0}};
      for (int k = 0; k <= dim; ++k) {
        std::array<int, 4> up = a;
        ++up[k];
        v = Add(v, Scale(level.at(up), l[k]));
      }
      next[a] = v;
    }
    level.swap(next);
  }
  return level.begin()->second;
}

TEST(ReferenceEvaluate, MatchesDeCasteljauOnSimplicesAndTensorProducts) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (CellType type : {CellType::Line, CellType::Tri, CellType::Tet}) {
    const int dim = ParamDimOf(type);
    for (int degree = 1; degree <= 6; ++degree) {
      RefCell cell;
      cell.type = type;
      cell.degrees = {{degree, 0, 0}};
      cell.ambientDim = 3;
      std::vector<Vec3> net(cell.numControlPoints());
      for (Vec3& p : net) {
        p = {{u(rng), u(rng), u(rng)}};
        cell.points.insert(cell.points.end(), p.begin(), p.end());
      }
      for (int trial = 0; trial < 10; ++trial) {
        const Vec3 ref = RandomRefPoint(type, rng);
        const Vec3 x = Eval(cell, ref);
        const Vec3 y = DeCasteljauSimplex(dim, degree, net, ref.data());
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(x[k], y[k], 1e-13) << "degree " << degree;
      }
    }
  }
  // Wedge (tri x line): de Casteljau over the triangle for each line index,
  // then along the line. Checks the tensor ordering (triangle net fastest).
  for (int p = 1; p <= 4; ++p) {
    for (int q = 1; q <= 3; ++q) {
      RefCell cell;
      cell.type = CellType::Wedge;
      cell.degrees = {{p, q, 0}};
      cell.ambientDim = 3;
      const int triSize = (p + 1) * (p + 2) / 2;
      std::vector<std::vector<Vec3>> layers(q + 1, std::vector<Vec3>(triSize));
      for (auto& layer : layers)
        for (Vec3& pt : layer) {
          pt = {{u(rng), u(rng), u(rng)}};
          cell.points.insert(cell.points.end(), pt.begin(), pt.end());
        }
      for (int trial = 0; trial < 10; ++trial) {
        const Vec3 ref = RandomRefPoint(CellType::Wedge, rng);
        std::vector<Vec3> column;
        for (const auto& layer : layers) column.push_back(DeCasteljauSimplex(2, p, layer, ref.data()));
        const Vec3 y = DeCasteljauSimplex(1, q, column, &ref[2]);
        const Vec3 x = Eval(cell, ref);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(x[k], y[k], 1e-13);
      }
    }
  }
}

TEST(ReferenceEvaluate, JetMatchesFiniteDifferences) {
  std::mt19937_64 rng(14);
  for (CellType type : kAllTypes) {
    const int pd = ParamDimOf(type);
    for (bool rational : {false, true}) {
      const RefCell cell = RandomCurvedCell(type, 3, rational, 3, rng);
      SCOPED_TRACE(Describe(cell));
      for (int trial = 0; trial < 5; ++trial) {
        const Vec3 ref = RandomRefPoint(type, rng);
        RefJet jet;
        RefEvaluateJet(cell, ref.data(), 2, &jet);
        const double h = 1e-5;
        for (int i = 0; i < pd; ++i) {
          Vec3 up = ref, dn = ref;
          up[i] += h;
          dn[i] -= h;
          RefJet jup, jdn;
          RefEvaluateJet(cell, up.data(), 1, &jup);
          RefEvaluateJet(cell, dn.data(), 1, &jdn);
          for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(jet.d1[k][i], (jup.x[k] - jdn.x[k]) / (2 * h), 1e-7 * cell.size());
            for (int j = 0; j < pd; ++j)
              EXPECT_NEAR(jet.d2[k][j][i], (jup.d1[k][j] - jdn.d1[k][j]) / (2 * h), 1e-5 * cell.size());
          }
        }
      }
    }
  }
}

TEST(ReferenceEvaluate, RationalQuarterCircleLiesOnTheCircle) {
  const RefCell arc = QuarterCircleArc({{0.5, -1.0}}, 2.0);
  for (int i = 0; i <= 100; ++i) {
    const Vec3 ref{{i / 100.0, 0, 0}};
    const Vec3 x = Eval(arc, ref);
    EXPECT_NEAR(std::hypot(x[0] - 0.5, x[1] + 1.0), 2.0, 1e-14);
  }
  // s = 1/2 is the 45 degree point by symmetry.
  const Vec3 mid = Eval(arc, {{0.5, 0, 0}});
  EXPECT_NEAR(mid[0] - 0.5, std::sqrt(2.0), 1e-14);
  EXPECT_NEAR(mid[1] + 1.0, std::sqrt(2.0), 1e-14);
}

TEST(ReferenceEvaluate, PoleQuadLiesOnTheSphereOctant) {
  const RefCell patch = PoleQuad();
  const Vec3 c = kPoleQuadCenter;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j) {
      const Vec3 x = Eval(patch, {{i / 20.0, j / 20.0, 0}});
      const Vec3 v = Sub(x, c);
      EXPECT_NEAR(Norm(v), kPoleQuadRadius, 1e-14);
      for (int k = 0; k < 3; ++k) EXPECT_GE(v[k], -1e-14);
    }
  // The whole t = 1 row is the pole.
  for (int i = 0; i <= 10; ++i) {
    const Vec3 x = Eval(patch, {{i / 10.0, 1.0, 0}});
    EXPECT_NEAR(x[2] - c[2], kPoleQuadRadius, 1e-14);
  }
}

TEST(ReferenceEvaluate, AdversarialCellsHaveTheirShape) {
  // C: the arc interpolates the circle at its ends (and at its middle, the
  // point (-r, 0), for even degrees); the mouth opens to +x.
  for (int degree = 2; degree <= 6; ++degree) {
    const RefCell c = CShapedQuad(degree);
    const Vec3 tip = Eval(c, {{0.0, 1.0, 0}});
    EXPECT_NEAR(tip[0], std::cos(M_PI / 6), 1e-12);
    EXPECT_NEAR(tip[1], 0.5, 1e-12);
    const Vec3 inner = Eval(c, {{0.5, 0.0, 0}});
    EXPECT_NEAR(inner[0], -0.5, degree % 2 == 0 ? 1e-12 : 0.2);
    EXPECT_NEAR(inner[1], 0.0, 1e-12);
  }
  // Spiral: radius grows along the arm, 1.25 turns.
  const RefCell spiral = SpiralQuad();
  double prev = 0.0;
  for (int i = 0; i <= 50; ++i) {
    const Vec3 x = Eval(spiral, {{i / 50.0, 0.5, 0}});
    const double r = std::hypot(x[0], x[1]);
    EXPECT_GT(r, prev - 0.05);
    prev = r;
  }
  const RefCell collapsed = CollapsedEdgeQuad();
  const Vec3 a = Eval(collapsed, {{0.1, 1.0, 0}}), b = Eval(collapsed, {{0.9, 1.0, 0}});
  EXPECT_EQ(a[0], b[0]);
  EXPECT_EQ(a[1], b[1]);
  const RefCell flat = ZeroAreaTriangle();
  std::mt19937_64 rng(15);
  for (int i = 0; i < 20; ++i) {
    const Vec3 x = Eval(flat, RandomRefPoint(CellType::Tri, rng));
    EXPECT_NEAR(x[1], -0.1 + 0.5 * (x[0] - 0.2), 1e-14);
  }
}

// ---------------------------------------------------------------------------
// Generators.

TEST(ReferenceGenerators, RandomPointsLieInTheDomain) {
  std::mt19937_64 rng(21);
  for (CellType type : kAllTypes) {
    int onFace = 0;
    for (int i = 0; i < 500; ++i) {
      const Vec3 u = RandomRefPoint(type, rng);
      EXPECT_TRUE(InReferenceDomain(type, u.data(), 0.0));
      Vec3 outward;
      const Vec3 b = RandomBoundaryRefPoint(type, rng, &outward);
      EXPECT_TRUE(InReferenceDomain(type, b.data(), 1e-15));
      EXPECT_GT(Norm(outward), 0.5);
      // Moving along the outward normal leaves the domain.
      const Vec3 out = Add(b, Scale(outward, 1e-6));
      EXPECT_FALSE(InReferenceDomain(type, out.data(), 1e-9));
      onFace += !InReferenceDomain(type, out.data(), 0.0);
    }
    EXPECT_EQ(onFace, 500);
  }
}

TEST(ReferenceGenerators, RandomCellsAreCurvedAndKeepTheirSize) {
  std::mt19937_64 rng(22);
  for (CellType type : kAllTypes) {
    const int pd = ParamDimOf(type);
    for (int degree = 2; degree <= 4; ++degree) {
      const RefCell cell = RandomCurvedCell(type, degree, false, std::max(pd, 2), rng);
      EXPECT_GT(cell.size(), 0.5);
      EXPECT_LT(cell.size(), 6.0);
      // The midpoint of a random segment in reference space maps away from
      // the chord's midpoint somewhere: the map is not affine.
      double maxBend = 0.0;
      for (int i = 0; i < 50; ++i) {
        const Vec3 u = RandomRefPoint(type, rng), v = RandomRefPoint(type, rng);
        const Vec3 mid = Scale(Add(u, v), 0.5);
        const Vec3 chordMid = Scale(Add(Eval(cell, u), Eval(cell, v)), 0.5);
        maxBend = std::max(maxBend, Norm(Sub(Eval(cell, mid), chordMid)));
      }
      EXPECT_GT(maxBend, 0.01 * cell.size()) << Describe(cell);
    }
  }
}

// ---------------------------------------------------------------------------
// Brute force against closed forms.

TEST(ReferenceBruteForce, SegmentDistances) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int ad = 2; ad <= 3; ++ad) {
    for (int degree = 1; degree <= 3; ++degree) {
      double a[3], b[3];
      RandomAffine(ad, 1, rng, a, b);
      const RefCell cell = AffineCell(CellType::Line, {{degree, 0, 0}}, ad, a, b);
      BruteForceReference ref(cell);
      const Vec3 p0 = Eval(cell, {{0, 0, 0}}), p1 = Eval(cell, {{1, 0, 0}});
      for (int i = 0; i < 200; ++i) {
        Vec3 p{{u(rng), u(rng), ad == 3 ? u(rng) : 0.0}};
        const RefClosest r = ref.Closest(p.data());
        EXPECT_NEAR(r.distance, DistanceToSegment(p, p0, p1), 1e-13);
        EXPECT_NEAR(Norm(Sub(Eval(cell, r.ref), p)), r.distance, 1e-13);
      }
    }
  }
}

TEST(ReferenceBruteForce, TriangleDistances) {
  std::mt19937_64 rng(32);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int ad = 2; ad <= 3; ++ad) {
    for (int degree = 1; degree <= 3; ++degree) {
      double a[6], b[3];
      RandomAffine(ad, 2, rng, a, b);
      const RefCell cell = AffineCell(CellType::Tri, {{degree, 0, 0}}, ad, a, b);
      BruteForceReference ref(cell);
      const Vec3 v0 = Eval(cell, {{0, 0, 0}}), v1 = Eval(cell, {{1, 0, 0}}), v2 = Eval(cell, {{0, 1, 0}});
      for (int i = 0; i < 300; ++i) {
        Vec3 p{{u(rng), u(rng), ad == 3 ? u(rng) : 0.0}};
        const RefClosest r = ref.Closest(p.data());
        EXPECT_NEAR(r.distance, DistanceToTriangle(p, v0, v1, v2), 1e-13) << "degree " << degree;
        EXPECT_TRUE(InReferenceDomain(CellType::Tri, r.ref.data(), 1e-14));
      }
    }
  }
  // Hand-checked: above the interior, and in a vertex's Voronoi region.
  const double a[6] = {1, 0, 0, 1, 0, 0}, b[3] = {0, 0, 0};
  const RefCell unit = AffineCell(CellType::Tri, {{1, 0, 0}}, 3, a, b);
  const double above[3] = {0.2, 0.3, 0.7}, corner[3] = {2.0, -1.0, 0.5};
  const RefClosest r1 = BruteForceClosest(unit, above), r2 = BruteForceClosest(unit, corner);
  EXPECT_NEAR(r1.distance, 0.7, 1e-15);
  EXPECT_NEAR(r1.ref[0], 0.2, 1e-14);
  EXPECT_NEAR(r1.ref[1], 0.3, 1e-14);
  EXPECT_NEAR(r2.distance, 1.5, 1e-15);
  EXPECT_NEAR(r2.ref[0], 1.0, 1e-14);
  EXPECT_NEAR(r2.ref[1], 0.0, 1e-14);
}

TEST(ReferenceBruteForce, TetAndHexDistances) {
  std::mt19937_64 rng(33);
  std::uniform_real_distribution<double> u(-1.0, 4.0);
  for (CellType type : {CellType::Tet, CellType::Hex, CellType::Wedge}) {
    for (int degree = 1; degree <= 2; ++degree) {
      double a[9], b[3];
      RandomAffine(3, 3, rng, a, b);
      for (double& v : b) v = 0.0;
      const RefCell cell = AffineCell(type, {{degree, degree, degree}}, 3, a, b);
      BruteForceReference ref(cell);
      // Boundary triangles of the affine solid.
      std::vector<std::array<Vec3, 3>> tris;
      auto quad = [&](Vec3 p, Vec3 q, Vec3 r, Vec3 s) {
        tris.push_back({{p, q, r}});
        tris.push_back({{p, r, s}});
      };
      auto x = [&](double s, double t, double w) { return Eval(cell, {{s, t, w}}); };
      if (type == CellType::Tet) {
        tris = {{{x(0, 0, 0), x(1, 0, 0), x(0, 1, 0)}}, {{x(0, 0, 0), x(1, 0, 0), x(0, 0, 1)}},
                {{x(0, 0, 0), x(0, 1, 0), x(0, 0, 1)}}, {{x(1, 0, 0), x(0, 1, 0), x(0, 0, 1)}}};
      } else if (type == CellType::Hex) {
        for (int axis = 0; axis < 3; ++axis)
          for (double side : {0.0, 1.0}) {
            Vec3 c[4];
            const double uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            for (int k = 0; k < 4; ++k) {
              Vec3 r{};
              r[axis] = side;
              r[(axis + 1) % 3] = uv[k][0];
              r[(axis + 2) % 3] = uv[k][1];
              c[k] = Eval(cell, r);
            }
            quad(c[0], c[1], c[2], c[3]);
          }
      } else {
        tris = {{{x(0, 0, 0), x(1, 0, 0), x(0, 1, 0)}}, {{x(0, 0, 1), x(1, 0, 1), x(0, 1, 1)}}};
        quad(x(0, 0, 0), x(1, 0, 0), x(1, 0, 1), x(0, 0, 1));
        quad(x(0, 0, 0), x(0, 1, 0), x(0, 1, 1), x(0, 0, 1));
        quad(x(1, 0, 0), x(0, 1, 0), x(0, 1, 1), x(1, 0, 1));
      }
      double m[3][3];
      for (int k = 0; k < 3; ++k)
        for (int i = 0; i < 3; ++i) m[k][i] = a[k * 3 + i];
      for (int i = 0; i < 200; ++i) {
        const Vec3 p{{u(rng), u(rng), u(rng)}};
        const Vec3 pre = Solve3(m, p);  // exact preimage of the affine map
        double expect = 0.0;
        if (!InReferenceDomain(type, pre.data(), 0.0)) {
          expect = std::numeric_limits<double>::infinity();
          for (const auto& t : tris) expect = std::min(expect, DistanceToTriangle(p, t[0], t[1], t[2]));
        }
        const RefClosest r = ref.Closest(p.data());
        EXPECT_NEAR(r.distance, expect, 1e-13) << invmap::CellTypeName(type) << " degree " << degree;
        if (expect == 0.0) {
          for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.ref[k], pre[k], 1e-12);
        }
      }
    }
  }
}

TEST(ReferenceBruteForce, QuarterCircleDistances) {
  const double cx = 0.5, cy = -1.0, radius = 2.0;
  const RefCell arc = QuarterCircleArc({{cx, cy}}, radius);
  BruteForceReference ref(arc);
  std::mt19937_64 rng(34);
  std::uniform_real_distribution<double> u(-4.0, 4.0);
  const Vec3 e0{{cx + radius, cy, 0}}, e1{{cx, cy + radius, 0}};
  for (int i = 0; i < 500; ++i) {
    const Vec3 p{{cx + u(rng), cy + u(rng), 0}};
    const double angle = std::atan2(p[1] - cy, p[0] - cx);
    const double expect = angle > 0 && angle < M_PI / 2
                              ? std::fabs(std::hypot(p[0] - cx, p[1] - cy) - radius)
                              : std::min(Norm(Sub(p, e0)), Norm(Sub(p, e1)));
    EXPECT_NEAR(ref.Closest(p.data()).distance, expect, 1e-13) << p[0] << ' ' << p[1];
  }
}

TEST(ReferenceBruteForce, SphereOctantDistances) {
  BruteForceReference ref(PoleQuad());
  std::mt19937_64 rng(35);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 400; ++i) {
    // Direction in the open positive octant; a quarter of them hug the pole,
    // where the patch is degenerate.
    Vec3 v{{u(rng), u(rng), u(rng) + (i % 4 == 0 ? 20.0 : 0.0)}};
    v = Scale(v, 1.0 / Norm(v));
    const double rho = kPoleQuadRadius * (0.1 + 2.5 * u(rng));
    const Vec3 p = Add(kPoleQuadCenter, Scale(v, rho));
    const RefClosest r = ref.Closest(p.data());
    EXPECT_NEAR(r.distance, std::fabs(rho - kPoleQuadRadius), 1e-12) << "direction " << v[0] << ' ' << v[1] << ' ' << v[2];
  }
}

/// On curved cells there is no closed form; a reference with a lattice twice
/// as fine and four times the starts must agree, or the default lattice
/// misses basins.
TEST(ReferenceBruteForce, AgreesWithADenserSearchOnCurvedCells) {
  std::mt19937_64 rng(36);
  const QueryKind kinds[] = {QueryKind::Inside, QueryKind::Near, QueryKind::Far, QueryKind::Boundary};
  for (CellType type : kAllTypes) {
    const int pd = ParamDimOf(type);
    for (int degree : {2, 4}) {
      for (bool rational : {false, true}) {
        const RefCell cell = RandomCurvedCell(type, degree, rational, 3, rng);
        BruteForceReference coarse(cell);
        BruteForceOptions denseOptions;
        denseOptions.divisions = pd == 1 ? 1024 : pd == 2 ? 160 : 56;
        denseOptions.maxStarts = 32;
        BruteForceReference dense(cell, denseOptions);
        for (int i = 0; i < 200; ++i) {
          const Query q = RandomQuery(cell, kinds[i % 4], rng);
          const RefClosest a = coarse.Closest(q.point.data()), b = dense.Closest(q.point.data());
          EXPECT_NEAR(a.distance, b.distance, 1e-12 * cell.size())
              << QueryKindName(q.kind) << "\n" << Describe(cell) << "query " << q.point[0] << ' ' << q.point[1] << ' '
              << q.point[2];
        }
      }
    }
  }
}

TEST(ReferenceBruteForce, DegenerateCellsGiveFiniteDistances) {
  std::mt19937_64 rng(37);
  std::uniform_real_distribution<double> u(-1.0, 2.0);
  for (const RefCell& cell : {CollapsedEdgeQuad(), ZeroAreaTriangle()}) {
    BruteForceReference ref(cell);
    for (int i = 0; i < 200; ++i) {
      const Vec3 p{{u(rng), u(rng), 0}};
      const RefClosest r = ref.Closest(p.data());
      ASSERT_TRUE(std::isfinite(r.distance));
      EXPECT_TRUE(InReferenceDomain(cell.type, r.ref.data(), 1e-14));
      EXPECT_NEAR(Norm(Sub(Eval(cell, r.ref), p)), r.distance, 1e-14);
    }
  }
  // A point of the (flat) image has distance 0.
  const RefCell flat = ZeroAreaTriangle();
  const Vec3 x = Eval(flat, {{0.3, 0.3, 0}});
  EXPECT_NEAR(BruteForceClosest(flat, x.data()).distance, 0.0, 1e-14);
}

}  // namespace
}  // namespace invmap::testing
