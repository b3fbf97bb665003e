// Enclosures of theta_v and its derivatives over boxes hold every value the
// point evaluation gives inside the box, and shrink with the box.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "pou/enclosure.h"
#include "tests/support/pou_meshes.h"

namespace invmap::pou {
namespace {

bool Holds(const Interval& i, double x) { return i.lo <= x && x <= i.hi; }

TEST(EnclosureTest, HoldsSampledValuesAndDerivatives) {
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int n : {3, 5, 6, 8}) {
    const testing::TriangleMesh m = testing::Bipyramid(n);
    PouSurface s;
    ASSERT_EQ(s.Build(m.xyz.data(), m.numVertices(), m.triangles.data(), m.numTriangles(), BaseKind::Loop, 0), "");
    double widest = 0.0;
    for (std::int64_t v = 0; v < s.numCharts(); ++v) {
      const double r = s.radius(v);
      for (int b = 0; b < 40; ++b) {
        const double w = r * std::pow(10.0, -4.0 * unit(random)) * 0.5;
        const double x0 = -0.9 * r / std::sqrt(2.0) + (1.8 * r / std::sqrt(2.0) - w) * unit(random);
        const double y0 = -0.9 * r / std::sqrt(2.0) + (1.8 * r / std::sqrt(2.0) - w) * unit(random);
        const ChartBox box{{x0, y0}, {x0 + w, y0 + w}};
        const ThetaEnclosure e = Enclose(s, v, box);
        for (int sample = 0; sample < 20; ++sample) {
          const double x = x0 + w * unit(random), y = y0 + w * unit(random);
          const ThetaJet j = s.Evaluate(v, x, y);
          for (int c = 0; c < 3; ++c) {
            ASSERT_TRUE(Holds(e.x[c].v, j.x[c].v)) << "chart " << v << " box at " << x0 << "," << y0 << " width " << w;
            ASSERT_TRUE(Holds(e.x[c].du, j.x[c].du) && Holds(e.x[c].dv, j.x[c].dv));
            ASSERT_TRUE(Holds(e.x[c].duu, j.x[c].duu) && Holds(e.x[c].duv, j.x[c].duv) && Holds(e.x[c].dvv, j.x[c].dvv))
                << "chart " << v << " box at " << x0 << "," << y0 << " width " << w << " coordinate " << c << ": "
                << e.x[c].duu.lo << " " << j.x[c].duu << " " << e.x[c].duu.hi;
          }
        }
        if (w < 1e-3 * r) {
          for (int c = 0; c < 3; ++c) widest = std::max(widest, e.x[c].v.width() / w);
        }
      }
    }
    // Narrow boxes: the value's range is about as wide as the box times the slope.
    EXPECT_LT(widest, 20.0) << n;
  }
}

}  // namespace
}  // namespace invmap::pou
