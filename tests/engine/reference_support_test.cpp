// Self-tests of the engine tests' references (tests/support/patch_reference,
// closest_reference, test_geometries): a wrong reference would make every
// comparison meaningless, so each piece is checked against a second,
// simpler computation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "tests/support/closest_reference.h"
#include "tests/support/patch_reference.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

/// Every cell of PatchCells, mapped at random reference points, must equal
/// EvaluateReported at the matching (cell, params): for B-splines this checks
/// the interpolation-based extraction against plain Cox-de Boor, for meshes
/// the FE-to-Bezier vertex reorder against FE shape functions.
void ExpectCellsMatchPatches(const Geometry& g, int samplesPerCell) {
  const std::vector<PatchCell> cells = GeometryCells(g);
  const std::vector<std::int64_t> counts = CellCounts(g);
  std::vector<std::int64_t> seen(g.patches.size(), 0);
  for (const PatchCell& pc : cells) ++seen[pc.patch];
  for (std::size_t p = 0; p < counts.size(); ++p) EXPECT_EQ(seen[p], counts[p]) << "patch " << p;
  const double size = GeometrySize(g);
  std::mt19937_64 rng(7);
  double worst = 0.0;
  for (const PatchCell& pc : cells) {
    for (int s = 0; s < samplesPerCell; ++s) {
      const std::array<double, 3> u = s == 0 ? RandomBoundaryRefPoint(pc.cell.type, rng) : RandomRefPoint(pc.cell.type, rng);
      double x[3] = {0, 0, 0}, y[3] = {0, 0, 0};
      RefEvaluate(pc.cell, u.data(), x);
      double params[3] = {NAN, NAN, NAN};
      for (int d = 0; d < pc.cell.paramDim(); ++d) params[d] = pc.paramLo[d] + pc.paramScale[d] * u[d];
      const std::string why = EvaluateReported(g, pc.patch, pc.index, params, 1e-12, y);
      ASSERT_TRUE(why.empty()) << why << " (patch " << pc.patch << " cell " << pc.index << ")";
      for (int k = 0; k < g.dimension; ++k) worst = std::max(worst, std::fabs(x[k] - y[k]));
    }
  }
  EXPECT_LE(worst, 1e-12 * size);
}

TEST(ReferenceSupportTest, BezierCellsReproducePatches) {
  ExpectCellsMatchPatches(WavySurfaces(), 3);
  ExpectCellsMatchPatches(BSplineCurves(2), 4);
  ExpectCellsMatchPatches(BSplineCurves(3), 4);
  ExpectCellsMatchPatches(BSplineVolumes(), 4);
  ExpectCellsMatchPatches(NurbsSphere({{0, 0, 0}}, 1.0), 20);
  ExpectCellsMatchPatches(NurbsTorus({{0, 0, 0}}, 1.0, 0.3), 20);
  ExpectCellsMatchPatches(MixedGeometry3(), 2);
  ExpectCellsMatchPatches(MixedGeometry2(), 2);
  ExpectCellsMatchPatches(QuadraticMesh(true), 2);
  ExpectCellsMatchPatches(QuadraticMesh(false), 2);
}

TEST(ReferenceSupportTest, AnalyticShapesLieOnTheirSurfaces) {
  // The NURBS constructions must be exact: points of every cell at distance 0.
  const Vec3 c{{0.3, -0.2, 0.1}};
  const Frame tilted = TiltedFrame(c);
  const Frame flat{{{0.3, -0.2, 0}}, {{1, 0, 0}}, {{0, 1, 0}}};
  struct Case {
    Geometry g;
    std::function<double(const double*)> distance;
  };
  std::vector<Case> cases;
  cases.push_back({NurbsSphere(c, 1.3), [&](const double* p) { return SphereDistance(c, 1.3, p); }});
  cases.push_back({NurbsTorus(c, 1.0, 0.35), [&](const double* p) { return TorusDistance(c, 1.0, 0.35, p); }});
  cases.push_back({NurbsCircle(3, tilted, 0.8), [&](const double* p) { return CircleDistance(3, tilted, 0.8, p); }});
  cases.push_back({NurbsCircle(2, flat, 0.8), [&](const double* p) { return CircleDistance(2, flat, 0.8, p); }});
  cases.push_back({NurbsAnnulus(3, tilted, 0.5, 1.1), [&](const double* p) { return AnnulusDistance(3, tilted, 0.5, 1.1, p); }});
  cases.push_back({NurbsAnnulus(2, flat, 0.5, 1.1), [&](const double* p) { return AnnulusDistance(2, flat, 0.5, 1.1, p); }});
  std::mt19937_64 rng(11);
  for (const Case& k : cases) {
    for (const PatchCell& pc : GeometryCells(k.g)) {
      for (int s = 0; s < 200; ++s) {
        const std::array<double, 3> u = RandomRefPoint(pc.cell.type, rng);
        double x[3] = {0, 0, 0};
        RefEvaluate(pc.cell, u.data(), x);
        EXPECT_LE(k.distance(x), 1e-14 * GeometrySize(k.g));
      }
    }
  }
}

TEST(ReferenceSupportTest, TriangleAndSegmentClosestPoints) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> coord(-1.0, 1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    double a[3], b[3], c[3], p[3];
    for (int k = 0; k < 3; ++k) a[k] = coord(rng), b[k] = coord(rng), c[k] = coord(rng), p[k] = 2 * coord(rng);
    if (trial % 10 == 0) {
      for (int k = 0; k < 3; ++k) c[k] = 0.3 * a[k] + 0.7 * b[k];  // degenerate: collinear
    }
    double s, t, x[3];
    ClosestOnTriangle(p, a, b, c, &s, &t, x);
    ASSERT_GE(s, -1e-15);
    ASSERT_GE(t, -1e-15);
    ASSERT_LE(s + t, 1 + 1e-15);
    double d = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double y = a[k] + s * (b[k] - a[k]) + t * (c[k] - a[k]);
      EXPECT_NEAR(y, x[k], 1e-14);
      d += (x[k] - p[k]) * (x[k] - p[k]);
    }
    d = std::sqrt(d);
    // Dense barycentric sampling can only be farther.
    double best = 1e300;
    const int n = 60;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        double e = 0.0;
        for (int k = 0; k < 3; ++k) {
          const double y = a[k] + (b[k] - a[k]) * i / n + (c[k] - a[k]) * j / n;
          e += (y - p[k]) * (y - p[k]);
        }
        best = std::min(best, std::sqrt(e));
      }
    EXPECT_LE(d, best + 1e-14);
    EXPECT_GE(d, best - 0.05);  // the lattice step bounds the sampling error
  }
}

TEST(ReferenceSupportTest, CulledSearchEqualsExhaustiveSearch) {
  // The tree's culling must never change the answer: compare with every
  // cell solved for a few hundred points of each kind.
  for (const Geometry& g : {MixedGeometry3(), MixedGeometry2()}) {
    ReferenceGeometry culled(g);
    const std::vector<PatchCell>& cells = culled.cells();
    std::vector<std::unique_ptr<BruteForceReference>> brute(cells.size());
    QueryMix mix;
    mix.on = 20;
    mix.near = 80;
    mix.mid = 60;
    mix.far = 60;
    mix.inside = 40;
    const QuerySet q = MakeQueries(cells, g.dimension, culled.size(), mix, 17);
    for (std::size_t i = 0; i < q.size(); ++i) {
      double p3[3] = {0, 0, 0};
      for (int k = 0; k < g.dimension; ++k) p3[k] = q.point(i)[k];
      double best = 1e300;
      for (std::size_t c = 0; c < cells.size(); ++c) {
        const RefCell& cell = cells[c].cell;
        double d;
        if (cells[c].linearSimplex) {
          double v[3][3] = {};
          for (int j = 0; j < cell.numControlPoints(); ++j)
            for (int k = 0; k < g.dimension; ++k) v[j][k] = cell.points[j * g.dimension + k];
          double s, t, x[3];
          if (cell.type == kernels::CellType::Tri) {
            ClosestOnTriangle(p3, v[0], v[1], v[2], &s, &t, x);
          } else {
            ClosestOnSegment(p3, v[0], v[1], &s, x);
          }
          d = std::sqrt((x[0] - p3[0]) * (x[0] - p3[0]) + (x[1] - p3[1]) * (x[1] - p3[1]) + (x[2] - p3[2]) * (x[2] - p3[2]));
        } else {
          if (!brute[c]) {
            BruteForceOptions o;
            o.divisions = ReferenceOptions().divisions[cell.paramDim() - 1];
            brute[c] = std::make_unique<BruteForceReference>(cell, o);
          }
          d = brute[c]->Closest(p3).distance;
        }
        best = std::min(best, d);
      }
      const ReferenceAnswer a = culled.Closest(q.point(i));
      EXPECT_NEAR(a.distance, best, 1e-12 * culled.size()) << "point " << i << " (" << q.kinds[i] << ")";
      // The answer's parameters must reproduce its point.
      double y[3];
      ASSERT_TRUE(EvaluateReported(g, a.patch, a.cell, a.params.data(), 1e-9, y).empty());
      for (int k = 0; k < g.dimension; ++k) EXPECT_NEAR(y[k], a.x[k], 1e-12 * culled.size());
    }
  }
}

}  // namespace
}  // namespace invmap::testing
