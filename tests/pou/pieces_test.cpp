// The pieces the search certifies with (pou/pieces.h, pou/piece_bounds.h):
// the bound of theta_v's third derivative over a box holds the third
// derivatives sampled in it (central differences of the second derivatives
// in random directions); every piece's image boxes (axis-aligned and
// oriented, and the hull of the oriented box's corners) hold theta_v at
// random points of its part of the kites; and the kites cover the surface: a random
// point of any chart lies, in the chart with the largest barycentric
// coordinate there, in a piece whose image box holds it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "pou/pieces.h"
#include "tests/support/pou_meshes.h"

namespace invmap::pou {
namespace {

struct Case {
  testing::TriangleMesh mesh;
  BaseKind base;
};

std::vector<Case> Cases() {
  return {{testing::Bipyramid(3), BaseKind::PnTriangles}, {testing::Bipyramid(5), BaseKind::Loop},
          {testing::Bipyramid(8), BaseKind::Flat},        {testing::Torus(8, 6, 2.0, 0.7), BaseKind::Loop},
          {testing::GenusTwo(2), BaseKind::PnTriangles}};
}

/// |D^3 theta [d, d, d]| for a unit direction d, by central differences of
/// the second derivative along d.
double ThirdAlong(const PouSurface& s, std::int64_t chart, double u, double v, double d0, double d1) {
  const double e = 1e-5 * s.radius(chart);
  const ThetaJet p = s.Evaluate(chart, u + e * d0, v + e * d1), q = s.Evaluate(chart, u - e * d0, v - e * d1);
  double sum = 0.0;
  for (int c = 0; c < 3; ++c) {
    const auto second = [&](const ThetaJet& j) {
      return d0 * d0 * j.x[c].duu + 2.0 * d0 * d1 * j.x[c].duv + d1 * d1 * j.x[c].dvv;
    };
    const double third = (second(p) - second(q)) / (2.0 * e);
    sum += third * third;
  }
  return std::sqrt(sum);
}

TEST(PiecesTest, ThirdDerivativeBoundHoldsSampledValues) {
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const Case& test : Cases()) {
    const testing::TriangleMesh& m = test.mesh;
    PouSurface s;
    ASSERT_EQ(s.Build(m.xyz.data(), m.numVertices(), m.triangles.data(), m.numTriangles(), test.base, 0), "");
    PieceSet set;
    std::vector<PieceBounds> bounds;
    set.Build(s, &bounds);
    BlendParts parts, scratch;
    BoxSample sample;
    int finite = 0;
    for (int trial = 0; trial < 400; ++trial) {
      const Piece& piece = set.pieces()[random() % set.pieces().size()];
      const ChartBox square = PieceBox(s, piece);
      const double side = (square.hi[0] - square.lo[0]) * std::pow(2.0, -static_cast<double>(random() % 5));
      const double u0 = square.lo[0] + (square.hi[0] - square.lo[0] - side) * unit(random);
      const double v0 = square.lo[1] + (square.hi[1] - square.lo[1] - side) * unit(random);
      const ChartBox box{{u0, v0}, {u0 + side, v0 + side}};
      const ShapeMajorants shapes = set.Shapes(piece);
      ReachingEdges(s, piece.chart, box, shapes, &parts);
      s.EvaluateParts(piece.chart, u0 + 0.5 * side, v0 + 0.5 * side, &parts);
      SampleBox(s, piece.chart, box, parts, SlackOf(s, piece.chart), &scratch, &sample);
      const double bound = ThirdDerivativeBound(s, piece.chart, box, shapes, sample);
      if (!(bound < HUGE_VAL)) continue;
      ++finite;
      for (int k = 0; k < 20; ++k) {
        const double a = 3.141592653589793 * unit(random);
        const double u = u0 + side * unit(random), v = v0 + side * unit(random);
        const double third = ThirdAlong(s, piece.chart, u, v, std::cos(a), std::sin(a));
        ASSERT_LE(third, bound * (1 + 1e-3)) << m.name << " chart " << piece.chart << " box " << u0 << " " << v0
                                             << " side " << side;
      }
    }
    // Boxes get an infinite bound only next to the chart's centre.
    EXPECT_GT(finite, 300) << m.name;
  }
}

TEST(PiecesTest, ImageBoxesHoldThePiecesPoints) {
  std::mt19937_64 random(12);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const Case& test : Cases()) {
    const testing::TriangleMesh& m = test.mesh;
    PouSurface s;
    ASSERT_EQ(s.Build(m.xyz.data(), m.numVertices(), m.triangles.data(), m.numTriangles(), test.base, 0), "");
    PieceSet set;
    std::vector<PieceBounds> bounds;
    set.Build(s, &bounds);
    ASSERT_EQ(bounds.size(), set.pieces().size());
    for (std::size_t i = 0; i < bounds.size(); ++i) {
      const Piece& piece = set.pieces()[i];
      const PieceBounds& b = bounds[i];
      const ChartBox square = PieceBox(s, piece);
      double corners[24];
      b.OrientedCorners(corners);
      for (int k = 0; k < 30; ++k) {
        const double u = square.lo[0] + (square.hi[0] - square.lo[0]) * unit(random);
        const double v = square.lo[1] + (square.hi[1] - square.lo[1]) * unit(random);
        if (OutsideKites(s, piece.chart, {{u, v}, {u, v}})) continue;
        double p[3];
        s.EvaluatePoint(piece.chart, u, v, p);
        for (int c = 0; c < 3; ++c) {
          ASSERT_TRUE(b.boxLo[c] <= p[c] && p[c] <= b.boxHi[c]) << m.name << " chart " << piece.chart;
        }
        // Inside the oriented box: along each axis, and within the corners'
        // hull (the corner nearest and farthest along the axis bracket it).
        for (int j = 0; j < 3; ++j) {
          const double along = b.axis[j][0] * p[0] + b.axis[j][1] * p[1] + b.axis[j][2] * p[2];
          ASSERT_TRUE(b.orientedLo[j] <= along && along <= b.orientedHi[j]) << m.name << " chart " << piece.chart;
          double least = HUGE_VAL, most = -HUGE_VAL;
          for (int corner = 0; corner < 8; ++corner) {
            const double at = b.axis[j][0] * corners[3 * corner] + b.axis[j][1] * corners[3 * corner + 1] +
                              b.axis[j][2] * corners[3 * corner + 2];
            least = std::min(least, at);
            most = std::max(most, at);
          }
          ASSERT_TRUE(least <= along && along <= most);
        }
      }
    }
  }
}

TEST(PiecesTest, KitesCoverTheSurface) {
  std::mt19937_64 random(13);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (const Case& test : Cases()) {
    const testing::TriangleMesh& m = test.mesh;
    PouSurface s;
    ASSERT_EQ(s.Build(m.xyz.data(), m.numVertices(), m.triangles.data(), m.numTriangles(), test.base, 0), "");
    PieceSet set;
    std::vector<PieceBounds> bounds;
    set.Build(s, &bounds);
    for (int k = 0; k < 2000; ++k) {
      const std::int64_t chart = static_cast<std::int64_t>(random() % s.numCharts());
      const double r = 0.85 * s.radius(chart);
      double u = r * unit(random), v = r * unit(random);
      if (std::hypot(u, v) > r) continue;
      double p[3];
      s.EvaluatePoint(chart, u, v, p);
      // The chart whose vertex is nearest in the canonical frames has the
      // largest barycentric coordinate there.
      const ChartPoint owner = s.Owner(chart, u, v);
      ASSERT_FALSE(OutsideKites(s, owner.chart, {{owner.u, owner.v}, {owner.u, owner.v}}))
          << m.name << " chart " << owner.chart << " at " << owner.u << " " << owner.v;
      bool covered = false;
      for (std::size_t i = 0; i < bounds.size(); ++i) {
        const Piece& piece = set.pieces()[i];
        const ChartBox square = PieceBox(s, piece);
        if (piece.chart != owner.chart || owner.u < square.lo[0] || owner.u > square.hi[0] ||
            owner.v < square.lo[1] || owner.v > square.hi[1]) {
          continue;
        }
        bool inside = true;
        for (int c = 0; c < 3; ++c) inside = inside && bounds[i].boxLo[c] <= p[c] && p[c] <= bounds[i].boxHi[c];
        covered = covered || inside;
      }
      ASSERT_TRUE(covered) << m.name << " chart " << chart << " at " << u << " " << v;
    }
  }
}

}  // namespace
}  // namespace invmap::pou
