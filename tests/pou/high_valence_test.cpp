// Vertices of any valence: the apexes of bipyramids with 3 to 32 sides and
// the centres of a cylinder's triangle-fan caps (valences 24 and 32). The
// transition maps unfold a chart's angles by n / 6, which at valence 12 and
// more passes a full turn within the chart: the search's blend (the parts
// pou/piece_bounds.h bounds) must still be theta_v, points of every chart
// must invert onto the surface, and answers must match the independent
// reference of tests/support/pou_reference.h (dense sampling of every chart
// and a polished local solve), with (cell, u, v) evaluating to the reported
// point.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <string>

#include "invmap/invmap.h"
#include "invmap/pou.h"
#include "pou/pou_surface.h"
#include "tests/pou/pou_test_support.h"

namespace invmap {
namespace {

using testing::TriangleMesh;

std::vector<TriangleMesh> Meshes() {
  std::vector<TriangleMesh> meshes;
  for (int n = 3; n <= 32; ++n) meshes.push_back(testing::Bipyramid(n));
  meshes.push_back(testing::Cylinder(24, 3));
  meshes.push_back(testing::Cylinder(32, 2));
  return meshes;
}

const PouBase kBases[] = {PouBase::Flat, PouBase::PnTriangles, PouBase::Loop};
const pou::BaseKind kBaseKinds[] = {pou::BaseKind::Flat, pou::BaseKind::PnTriangles, pou::BaseKind::Loop};

// The blend the search evaluates (every neighbour asked for) is the chart's
// theta_v with its derivatives, at points all over the p-domain.
TEST(PouHighValenceTest, SearchBlendIsTheChart) {
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int index = 0;
  for (const TriangleMesh& m : Meshes()) {
    pou::PouSurface surface;
    ASSERT_EQ(surface.Build(m.xyz.data(), m.numVertices(), m.triangles.data(), m.numTriangles(),
                            kBaseKinds[index++ % 3], 0),
              "")
        << m.name;
    const double size = m.diagonal();
    double worst = 0.0;
    for (std::int64_t v = 0; v < surface.numCharts(); ++v) {
      pou::BlendParts parts;
      for (int e = 0; e < surface.valence(v); ++e) parts.edges.push_back(e);
      const double r = surface.radius(v);
      for (int sample = 0; sample < 60; ++sample) {
        const double x = r * unit(random), y = r * unit(random);
        if (!(std::hypot(x, y) < 0.99 * r)) continue;
        surface.EvaluateParts(v, x, y, &parts);
        const pou::ThetaJet blend = parts.Theta(), chart = surface.Evaluate(v, x, y);
        for (int c = 0; c < 3; ++c) {
          const pou::Jet<double>& a = blend.x[c];
          const pou::Jet<double>& b = chart.x[c];
          worst = std::max({worst, std::fabs(a.v - b.v), r * std::fabs(a.du - b.du), r * std::fabs(a.dv - b.dv),
                            r * r * std::fabs(a.duu - b.duu), r * r * std::fabs(a.duv - b.duv),
                            r * r * std::fabs(a.dvv - b.dvv)});
        }
      }
    }
    EXPECT_LE(worst, 1e-12 * size) << m.name;
  }
}

// theta_v(p) by the independent evaluator, for p anywhere in the p-domain of
// any chart (the apexes' most of all), is on the surface: found at distance 0.
TEST(PouHighValenceTest, ChartPointsInvertOntoTheSurface) {
  std::mt19937_64 random(23);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int index = 0;
  for (const TriangleMesh& m : Meshes()) {
    testing::BuiltPou b;
    testing::BuildPou(m, kBases[index++ % 3], &b);
    if (::testing::Test::HasFatalFailure()) return;
    const testing::PouReference reference(b.patch.points, b.patch.cells, b.patch.degrees, b.patch.chartControlPoints);
    const double size = m.diagonal();
    std::vector<double> points;
    for (int i = 0; i < 60; ++i) {
      // Half the points on the highest-valence vertex's chart (vertex 0 of a
      // bipyramid, the last two of a cylinder), the others anywhere.
      std::int64_t v = static_cast<std::int64_t>(random() % m.numVertices());
      if (i % 2 == 0) v = m.name.rfind("cylinder", 0) == 0 ? m.numVertices() - 1 - i % 4 / 2 : 0;
      const double r = reference.radius(v) * std::sqrt(0.98 * unit(random)), a = 2.0 * M_PI * unit(random);
      double p[3];
      reference.Evaluate(v, std::polar(r, a), p);
      points.insert(points.end(), p, p + 3);
    }
    Results results;
    ASSERT_EQ(b.built.manifold.Invert(PointsView::Interleaved(points.data(), points.size() / 3, 3), {}, &results),
              Error::Ok);
    double worst = 0.0;
    for (std::size_t i = 0; i < points.size() / 3; ++i) {
      ASSERT_EQ(results.status[i], Status::Found) << m.name << " point " << i;
      worst = std::max(worst, results.distance[i]);
    }
    EXPECT_LE(worst, 1e-9 * size) << m.name;
  }
}

// Points on, near and away from the surface: never farther than the
// reference beyond 1e-9 of the size, within 1e-7 of it, and the reported
// chart and coordinates evaluate (by the reference) to the reported point.
TEST(PouHighValenceTest, MatchesTheIndependentReference) {
  std::mt19937_64 random(31);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int index = 0;
  for (const TriangleMesh& m : Meshes()) {
    testing::BuiltPou b;
    testing::BuildPou(m, kBases[(index++ + 1) % 3], &b);
    if (::testing::Test::HasFatalFailure()) return;
    const testing::PouReference reference(b.patch.points, b.patch.cells, b.patch.degrees, b.patch.chartControlPoints);
    const double size = m.diagonal();
    std::vector<double> points;
    for (double offset : {0.0, 0.01, 0.05, 0.1, 0.3, 0.6, 1.0}) {
      // Points over the apex's star (or a cap's) and anywhere.
      const bool apex = points.size() % 2 == 0;
      const std::int64_t v = apex ? (m.name.rfind("cylinder", 0) == 0 ? m.numVertices() - 1 : 0)
                                  : static_cast<std::int64_t>(random() % m.numVertices());
      const double r = 0.95 * reference.radius(v);
      double p[3];
      reference.Evaluate(v, {r * unit(random) / std::sqrt(2.0), r * unit(random) / std::sqrt(2.0)}, p);
      testing::PushMovedPoint(p, offset * size, random, unit, &points);
    }
    Results results;
    ASSERT_EQ(b.built.manifold.Invert(PointsView::Interleaved(points.data(), points.size() / 3, 3), {}, &results),
              Error::Ok);
    testing::ExpectTheReferenceMinima(reference, points, results, size, m.name);
  }
}

// Points scattered around and inside a bipyramid whose apexes have valence
// 32 under Loop's base: a nearly flat, wide star where a query far below an
// apex leaves many boxes of similar distance. With a search budget of 4096
// boxes 60 of 3000 such points (2 %) came out farther than the surface;
// every answer must be the reference's, by `pointwise` too.
TEST(PouHighValenceTest, PointsAroundAWideFlatStarFindTheGlobalMinimum) {
  const TriangleMesh m = testing::Bipyramid(32);
  testing::BuiltPou b;
  testing::BuildPou(m, PouBase::Loop, &b);
  if (::testing::Test::HasFatalFailure()) return;
  const testing::PouReference reference(b.patch.points, b.patch.cells, b.patch.degrees, b.patch.chartControlPoints);
  const double size = m.diagonal();
  std::mt19937_64 random(2);
  std::normal_distribution<double> normal(0.0, 0.6 * size);
  std::vector<double> points(3 * 150);
  for (double& x : points) x = normal(random);
  for (const bool pointwise : {false, true}) {
    InversionOptions options;
    options.pointwise = pointwise;
    options.threads = 1;
    Results results;
    ASSERT_EQ(
        b.built.manifold.Invert(PointsView::Interleaved(points.data(), points.size() / 3, 3), options, &results),
        Error::Ok);
    for (std::size_t i = 0; i < points.size() / 3; ++i) {
      const std::string where = "point " + std::to_string(i) + (pointwise ? " pointwise" : "");
      std::int64_t chart;
      std::complex<double> at;
      const double expected = reference.Closest(&points[3 * i], &chart, &at);
      ASSERT_EQ(results.status[i], Status::Found) << where;
      EXPECT_LE(results.distance[i], expected + 1e-9 * size) << where;
    }
  }
}

}  // namespace
}  // namespace invmap
