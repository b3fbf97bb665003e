// Inversion onto partition-of-unity surfaces through the public API, against
// the independent reference of tests/support/pou_reference.h (dense sampling
// of every chart and a polished local solve), on meshes with vertices of
// valence 3 to 8, a torus and a genus-2 surface, each base surface, for
// points on the surface, near it, a tenth of its size away and twice its
// size away: the distance is never larger than the reference's (beyond the
// tolerance), agrees with it, the reported chart and coordinates evaluate to
// the reported point, and the chart is the one answering for that point
// (within 2R/3 of its centre, where its kites lie).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <string>

#include "invmap/invmap.h"
#include "invmap/pou.h"
#include "tests/pou/pou_test_support.h"

namespace invmap {
namespace {

struct Case {
  testing::TriangleMesh mesh;
  PouBase base;
};

TEST(PouInversionTest, MatchesTheIndependentReference) {
  std::vector<Case> cases;
  const PouBase bases[] = {PouBase::Flat, PouBase::PnTriangles, PouBase::Loop};
  for (int n = 3; n <= 8; ++n) cases.push_back({testing::Bipyramid(n), bases[n % 3]});
  cases.push_back({testing::Torus(8, 6, 2.0, 0.7), PouBase::Loop});
  cases.push_back({testing::GenusTwo(2), PouBase::PnTriangles});
  std::mt19937_64 random(17);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (const Case& test : cases) {
    const testing::TriangleMesh& m = test.mesh;
    testing::BuiltPou b;
    testing::BuildPou(m, test.base, &b);
    if (::testing::Test::HasFatalFailure()) return;
    const testing::PouReference reference(b.patch.points, b.patch.cells, b.patch.degrees, b.patch.chartControlPoints);
    const double size = m.diagonal();
    // A random point of a random chart, moved off the surface by the offset
    // in a random direction.
    std::vector<double> points;
    for (double offset : {0.0, 0.0, 0.01, 0.01, 0.03, 0.1, 0.1, 0.1, 2.0, 2.0}) {
      const std::int64_t v = static_cast<std::int64_t>(random() % m.numVertices());
      const double r = 0.6 * reference.radius(v);
      double p[3];
      reference.Evaluate(v, {r * unit(random), r * unit(random)}, p);
      testing::PushMovedPoint(p, offset * size, random, unit, &points);
    }
    Results results;
    ASSERT_EQ(b.built.manifold.Invert(PointsView::Interleaved(points.data(), points.size() / 3, 3), {}, &results),
              Error::Ok);
    testing::ExpectTheReferenceMinima(reference, points, results, size, m.name);
    for (std::size_t i = 0; i < points.size() / 3; ++i) {
      const std::string where = m.name + " point " + std::to_string(i);
      ASSERT_EQ(results.status[i], Status::Found) << where;
      EXPECT_EQ(results.patch[i], 0);
      const double u = results.params[3 * i], v = results.params[3 * i + 1];
      EXPECT_LE(std::hypot(u, v), (2.0 / 3.0 + 1e-9) * b.charts.Radius(results.cell[i])) << where;
      ChartJet jet;
      ASSERT_TRUE(b.charts.Evaluate(results.cell[i], u, v, &jet));
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(jet.point[c], results.closest[3 * i + c], 1e-12 * size);
      double gap = 0.0;
      for (int c = 0; c < 3; ++c) gap += std::pow(results.closest[3 * i + c] - points[3 * i + c], 2);
      EXPECT_NEAR(std::sqrt(gap), results.distance[i], 1e-12 * size);
    }
  }
}

}  // namespace
}  // namespace invmap
