// First and second derivatives of the blended parametrizations: they match
// finite differences of theta_v itself, and of theta_u composed with the
// transition map (the same surface seen through a neighbouring chart), and
// they are continuous where the set of charts that contribute changes (the
// rim of a gluing domain, the rays between star triangles, the disk where
// only the chart's own shape function counts).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include "pou/chart_maps.h"
#include "pou/pou_surface.h"
#include "tests/support/pou_meshes.h"

namespace invmap::pou {
namespace {

using Map = std::function<bool(double, double, double*)>;

/// Largest difference between the jet at (x, y) and central differences of
/// `f` with step h: first derivatives, then second ones.
void CompareWithDifferences(const ThetaJet& jet, const Map& f, double x, double y, double h, double* first,
                            double* second) {
  double c[3], xp[3], xm[3], yp[3], ym[3], pp[3], pm[3], mp[3], mm[3];
  if (!f(x, y, c) || !f(x + h, y, xp) || !f(x - h, y, xm) || !f(x, y + h, yp) || !f(x, y - h, ym) ||
      !f(x + h, y + h, pp) || !f(x + h, y - h, pm) || !f(x - h, y + h, mp) || !f(x - h, y - h, mm)) {
    return;
  }
  for (int k = 0; k < 3; ++k) {
    const Jet<double>& j = jet.x[k];
    *first = std::max({*first, std::fabs(j.du - (xp[k] - xm[k]) / (2 * h)), std::fabs(j.dv - (yp[k] - ym[k]) / (2 * h))});
    *second = std::max({*second, std::fabs(j.duu - (xp[k] - 2 * c[k] + xm[k]) / (h * h)),
                        std::fabs(j.dvv - (yp[k] - 2 * c[k] + ym[k]) / (h * h)),
                        std::fabs(j.duv - (pp[k] - pm[k] - mp[k] + mm[k]) / (4 * h * h))});
  }
}

double JetDistance(const ThetaJet& a, const ThetaJet& b) {
  double d = 0.0;
  for (int k = 0; k < 3; ++k) {
    d = std::max({d, std::fabs(a.x[k].v - b.x[k].v), std::fabs(a.x[k].du - b.x[k].du), std::fabs(a.x[k].dv - b.x[k].dv),
                  std::fabs(a.x[k].duu - b.x[k].duu), std::fabs(a.x[k].duv - b.x[k].duv),
                  std::fabs(a.x[k].dvv - b.x[k].dvv)});
  }
  return d;
}

std::vector<testing::TriangleMesh> Meshes() {
  std::vector<testing::TriangleMesh> meshes;
  for (int n = 3; n <= 8; ++n) meshes.push_back(testing::Bipyramid(n));
  meshes.push_back(testing::GenusTwo(2));
  return meshes;
}

TEST(DerivativesTest, MatchDifferencesInTheChartAndThroughItsNeighbours) {
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (const auto& m : Meshes()) {
    PouSurface s;
    ASSERT_EQ(s.Build(m.xyz.data(), m.numVertices(), m.triangles.data(), m.numTriangles(), BaseKind::Loop, 0), "");
    double own1 = 0, own2 = 0, other1 = 0, other2 = 0;
    int through = 0;
    for (std::int64_t v = 0; v < s.numCharts(); ++v) {
      const double r = s.radius(v), h = 1e-4 * r;
      for (int sample = 0; sample < 60; ++sample) {
        const double x = r * unit(random), y = r * unit(random);
        if (std::hypot(x, y) > 0.97 * r) continue;
        const ThetaJet jet = s.Evaluate(v, x, y);
        CompareWithDifferences(jet, [&](double a, double b, double* p) { s.EvaluatePoint(v, a, b, p); return true; },
                               x, y, h, &own1, &own2);
        for (int edge = 0; edge < s.valence(v); ++edge) {
          double qx, qy;
          if (!s.Transition(v, edge, x, y, &qx, &qy)) continue;
          const std::int64_t u = s.mesh().neighbor(v, edge);
          const Map throughNeighbour = [&](double a, double b, double* p) {
            double ca, cb;
            if (!s.Transition(v, edge, a, b, &ca, &cb)) return false;
            s.EvaluatePoint(u, ca, cb, p);
            return true;
          };
          CompareWithDifferences(jet, throughNeighbour, x, y, h, &other1, &other2);
          ++through;
        }
      }
    }
    EXPECT_GT(through, 50) << m.name;
    EXPECT_LT(own1, 1e-6) << m.name;
    EXPECT_LT(own2, 1e-4) << m.name;
    EXPECT_LT(other1, 1e-6) << m.name;
    EXPECT_LT(other2, 1e-4) << m.name;
  }
}

TEST(DerivativesTest, ContinuousWhereTheContributingChartsChange) {
  for (const auto& m : Meshes()) {
    PouSurface s;
    ASSERT_EQ(s.Build(m.xyz.data(), m.numVertices(), m.triangles.data(), m.numTriangles(), BaseKind::PnTriangles, 0),
              "");
    double worst = 0.0;
    const double eps = 1e-9;
    for (std::int64_t v = 0; v < s.numCharts(); ++v) {
      const int n = s.valence(v);
      const double r = s.radius(v);
      const auto polar = [&](double radius, double angle) {
        return std::make_pair(radius * std::cos(angle), radius * std::sin(angle));
      };
      for (int edge = 0; edge < n; ++edge) {
        const double ray = 2.0 * kPi * edge / n;
        // Across the ray of the edge (the sector changes there).
        for (double t : {0.3, 0.6, 0.9}) {
          const auto [x0, y0] = polar(t * r, ray - eps);
          const auto [x1, y1] = polar(t * r, ray + eps);
          worst = std::max(worst, JetDistance(s.Evaluate(v, x0, y0), s.Evaluate(v, x1, y1)));
        }
        // Across the rim of the gluing domain with this neighbour: canonical
        // points at distance sqrt(3)/2 from (1, 0), mapped into the chart.
        for (double phi : {2.4, 2.7, 3.0, 3.3, 3.6, 3.9}) {
          for (double side : {-1.0, 1.0}) {
            const double d = kFrameRadius * (1.0 + side * eps);
            const double cx = 1.0 + d * std::cos(phi), cy = d * std::sin(phi);
            const double rho = std::hypot(cx, cy), a = std::atan2(cy, cx) * 6.0 / n + ray;
            if (rho >= kFrameRadius) continue;
            const auto [x, y] = polar(rho * r / kFrameRadius, a);
            const auto [xo, yo] = polar(rho * r / kFrameRadius * (1.0 - 2.0 * side * eps), a);
            worst = std::max(worst, JetDistance(s.Evaluate(v, x, y), s.Evaluate(v, xo, yo)));
          }
        }
      }
      // Across the circle inside which only the chart's own shape function counts.
      for (double a = 0.1; a < 6.2; a += 0.7) {
        const auto [x0, y0] = polar(0.1547 * r * (1 - eps), a);
        const auto [x1, y1] = polar(0.1547 * r * (1 + eps), a);
        worst = std::max(worst, JetDistance(s.Evaluate(v, x0, y0), s.Evaluate(v, x1, y1)));
      }
    }
    EXPECT_LT(worst, 1e-6) << m.name;
  }
}

}  // namespace
}  // namespace invmap::pou
