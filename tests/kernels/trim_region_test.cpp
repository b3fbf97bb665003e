// The trimmed region's tests against exact geometry: a square with a round
// hole (straight pieces and rational quadratic arcs) and a loop of cubic
// pieces, points and boxes anywhere, on and within a hair of the boundary.
#include "kernels/trim_region.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace invmap::kernels {
namespace {

using Side = TrimRegion::Side;

/// The square [0, 10]^2 less the disk of radius 3 about (5, 5): the square
/// in four segments, the circle in four quarter arcs (weights 1, cos 45, 1).
TrimRegion SquareWithHole(bool reverse) {
  TrimRegion region;
  const double square[5][2] = {{0, 0}, {10, 0}, {10, 10}, {0, 10}, {0, 0}};
  for (int k = 0; k < 4; ++k) {
    const int a = reverse ? 4 - k : k, b = reverse ? 3 - k : k + 1;
    const double uv[4] = {square[a][0], square[a][1], square[b][0], square[b][1]};
    region.AddPiece(1, uv, nullptr);
  }
  const double w[3] = {1.0, std::sqrt(0.5), 1.0};
  for (int q = 0; q < 4; ++q) {
    const double a0 = q * M_PI / 2, a1 = a0 + M_PI / 2, m = a0 + M_PI / 4;
    double uv[6] = {5 + 3 * std::cos(a0), 5 + 3 * std::sin(a0), 5 + 3 * std::sqrt(2.0) * std::cos(m),
                    5 + 3 * std::sqrt(2.0) * std::sin(m), 5 + 3 * std::cos(a1), 5 + 3 * std::sin(a1)};
    // Quarter ends are computed once and reused bit for bit by the next.
    if (q == 3) {
      uv[4] = 5 + 3 * std::cos(0.0);
      uv[5] = 5 + 3 * std::sin(0.0);
    }
    region.AddPiece(2, uv, w);
  }
  region.Finish();
  return region;
}

/// Signed distance to the region's boundary: negative inside.
double ExactSigned(double u, double v) {
  const double outSquare = std::hypot(std::max({-u, 0.0, u - 10}), std::max({-v, 0.0, v - 10}));
  const double inSquare = std::min({u, 10 - u, v, 10 - v});
  const double toCircle = std::hypot(u - 5, v - 5) - 3;  // positive outside the disk
  if (outSquare > 0.0) return outSquare;
  if (toCircle < 0.0) return -toCircle;  // in the hole: outside the region
  return -std::min(inSquare, toCircle);
}

TEST(TrimRegion, PointsOnEitherSideAndOnTheBoundary) {
  for (const bool reverse : {false, true}) {
    const TrimRegion region = SquareWithHole(reverse);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> coord(-2.0, 12.0);
    int wrong = 0, crossingFar = 0;
    for (int i = 0; i < 20000; ++i) {
      double p[2] = {coord(rng), coord(rng)};
      if (i % 4 == 0) {
        // A point of the boundary moved off it by 1e-14 to 1e-4.
        const double a = coord(rng);
        const double offset = std::pow(10.0, -14.0 + 10.0 * (i % 1000) / 1000.0) * (i % 8 == 0 ? 1 : -1);
        const double r = 3 + offset;
        p[0] = 5 + r * std::cos(a);
        p[1] = 5 + r * std::sin(a);
      }
      const double s = ExactSigned(p[0], p[1]);
      const Side side = region.ClassifyPoint(p);
      if (side == Side::Crossing) {
        crossingFar += std::abs(s) > 1e-9 ? 1 : 0;
      } else {
        wrong += (side == Side::Inside) != (s < 0.0) ? 1 : 0;
      }
    }
    EXPECT_EQ(wrong, 0);
    EXPECT_EQ(crossingFar, 0) << "points called on the boundary though 1e-9 or more off it";
  }
}

TEST(TrimRegion, BoxesInsideOutsideOrCrossing) {
  const TrimRegion region = SquareWithHole(false);
  const double lo[2] = {-1, -1}, hi[2] = {11, 11};
  const TrimPieces near = region.PiecesFor(lo, hi);
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> coord(-2.0, 12.0), unit(0.0, 1.0);
  int wrong = 0, crossingFar = 0;
  for (int i = 0; i < 20000; ++i) {
    const double size = std::pow(10.0, -8.0 * unit(rng));
    const double c[2] = {coord(rng), coord(rng)};
    const double blo[2] = {c[0] - size * unit(rng), c[1] - size * unit(rng)};
    const double bhi[2] = {c[0] + size * unit(rng), c[1] + size * unit(rng)};
    // Whether the boundary meets the box, exactly: the square's outline
    // does unless the box misses the square or lies in its interior; the
    // circle does when its radius lies between the box's nearest and
    // farthest distances from the centre.
    const bool overlapsSquare = blo[0] <= 10 && bhi[0] >= 0 && blo[1] <= 10 && bhi[1] >= 0;
    const bool inInterior = blo[0] > 0 && bhi[0] < 10 && blo[1] > 0 && bhi[1] < 10;
    const double nearest = std::hypot(std::max({blo[0] - 5, 0.0, 5 - bhi[0]}), std::max({blo[1] - 5, 0.0, 5 - bhi[1]}));
    const double farthest = std::hypot(std::max(std::abs(blo[0] - 5), std::abs(bhi[0] - 5)),
                                       std::max(std::abs(blo[1] - 5), std::abs(bhi[1] - 5)));
    const bool meets = (overlapsSquare && !inInterior) || (nearest <= 3 && farthest >= 3);
    const double half = std::hypot(bhi[0] - blo[0], bhi[1] - blo[1]) / 2;
    const double s = ExactSigned((blo[0] + bhi[0]) / 2, (blo[1] + bhi[1]) / 2);
    const Side side = region.ClassifyBox(blo, bhi, near);
    if (side == Side::Crossing) {
      // Conservative, but only near the boundary: pieces are halved down
      // to the box's size.
      crossingFar += std::abs(s) > 3 * half + 1e-9 ? 1 : 0;
    } else {
      wrong += meets || (side == Side::Inside) != (s < 0.0) ? 1 : 0;
    }
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(crossingFar, 0);
}

TEST(TrimRegion, CubicLoopAgainstDenseSampling) {
  // A closed loop of two cubic pieces (a lens), checked against the
  // even-odd count of a dense polyline of the curve itself.
  const double top[8] = {0, 0, 1, 3, 4, 3, 5, 0}, bottom[8] = {5, 0, 4, -2, 1, -2, 0, 0};
  TrimRegion region;
  region.AddPiece(3, top, nullptr);
  region.AddPiece(3, bottom, nullptr);
  region.Finish();
  std::vector<double> polyline;
  for (const double* net : {top, bottom}) {
    for (int k = 0; k < 4000; ++k) {
      const double t = k / 4000.0, s = 1 - t;
      const double b[4] = {s * s * s, 3 * s * s * t, 3 * s * t * t, t * t * t};
      polyline.push_back(b[0] * net[0] + b[1] * net[2] + b[2] * net[4] + b[3] * net[6]);
      polyline.push_back(b[0] * net[1] + b[1] * net[3] + b[2] * net[5] + b[3] * net[7]);
    }
  }
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 6), v(-3, 4);
  int wrong = 0;
  for (int i = 0; i < 3000; ++i) {
    const double p[2] = {u(rng), v(rng)};
    bool inside = false;
    double nearest = 1e300;
    const std::size_t n = polyline.size() / 2;
    for (std::size_t k = 0; k < n; ++k) {
      const double* a = &polyline[2 * k];
      const double* b = &polyline[2 * ((k + 1) % n)];
      nearest = std::min(nearest, std::hypot(a[0] - p[0], a[1] - p[1]));
      if ((a[1] > p[1]) != (b[1] > p[1]) && p[0] < a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1])) {
        inside = !inside;
      }
    }
    if (nearest < 1e-2) continue;  // the polyline's own error
    const Side side = region.ClassifyPoint(p);
    wrong += side == Side::Crossing || (side == Side::Inside) != inside ? 1 : 0;
  }
  EXPECT_EQ(wrong, 0);
}

}  // namespace
}  // namespace invmap::kernels
