// The cheap lower bounds that prune pairs of BVH nodes and cells: never
// above the true distance (random boxes and simplices under random rigid
// motions, dense samples of both sets), and tight where they are meant to
// be (thin boxes facing each other, parallel triangles). And the closed
// form between two triangles against the tests' own (random, facing and
// coplanar pairs).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "engine/pair_bounds.h"
#include "kernels/simplex_pair.h"
#include "tests/support/pair_reference.h"

namespace invmap::engine {
namespace {

kernels::RigidMotion RandomMotion(std::mt19937_64& rng, double reach) {
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> u(-reach, reach);
  double q[4] = {n(rng), n(rng), n(rng), n(rng)};
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (double& x : q) x /= norm;
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  kernels::RigidMotion m;
  const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                          {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                          {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m.rotation[i][j] = r[i][j];
    m.translation[i] = u(rng);
  }
  return m;
}

/// Points of a random patch: a flat or bent sheet of random size, tilt and place.
std::vector<double> RandomSheet(std::mt19937_64& rng, int count) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double sx = 0.05 + std::abs(u(rng)), sy = 0.05 + std::abs(u(rng)), bend = 0.3 * u(rng);
  const kernels::RigidMotion place = RandomMotion(rng, 1.0);
  std::vector<double> points;
  for (int i = 0; i < count; ++i) {
    const double a = u(rng), b = u(rng);
    const double local[3] = {sx * a, sy * b, bend * (a * a + b * b)};
    double x[3];
    place.Apply(local, x);
    points.insert(points.end(), x, x + 3);
  }
  return points;
}

/// Points spread over a box: its corners and random points on its faces.
std::vector<double> BoxSamples(const OrientedBounds& box, std::mt19937_64& rng, int count) {
  std::vector<double> points(24);
  OrientedCorners(box, points.data());
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < count; ++i) {
    double c[3] = {u(rng), u(rng), u(rng)};
    c[i % 3] = c[i % 3] < 0 ? -1.0 : 1.0;  // on a face
    for (int k = 0; k < 3; ++k) {
      double v = box.center[k];
      for (int a = 0; a < 3; ++a) v += c[a] * box.half[a] * box.axis[a][k];
      points.push_back(v);
    }
  }
  return points;
}

double MinDistance(const std::vector<double>& a, const std::vector<double>& b, const kernels::RigidMotion& bIntoA) {
  double best = INFINITY;
  for (std::size_t j = 0; j < b.size(); j += 3) {
    double y[3];
    bIntoA.Apply(&b[j], y);
    for (std::size_t i = 0; i < a.size(); i += 3) {
      const double d[3] = {a[i] - y[0], a[i + 1] - y[1], a[i + 2] - y[2]};
      best = std::min(best, std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
    }
  }
  return best;
}

OrientedBounds Fit(const std::vector<double>& points) {
  const double origin[3] = {0.1, -0.2, 0.3};
  return FitOrientedBounds(PointMoments::Of(points.data(), points.size() / 3), origin, points.data(),
                           static_cast<int>(points.size() / 3));
}

TEST(PairBounds, OrientedBoundsHoldTheirPoints) {
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const std::vector<double> points = RandomSheet(rng, 20);
    const OrientedBounds box = Fit(points);
    for (std::size_t i = 0; i < points.size(); i += 3) {
      for (int a = 0; a < 3; ++a) {
        double t = 0.0;
        for (int k = 0; k < 3; ++k) t += box.axis[a][k] * (points[i + k] - box.center[k]);
        EXPECT_LE(std::abs(t), box.half[a]);
      }
    }
  }
}

TEST(PairBounds, OrientedLowerBoundNeverExceedsTheDistance) {
  std::mt19937_64 rng(11);
  int positive = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const OrientedBounds a = Fit(RandomSheet(rng, 12));
    const OrientedBounds b = Fit(RandomSheet(rng, 12));
    const kernels::RigidMotion motion = RandomMotion(rng, trial % 2 ? 3.0 : 1.0);
    const double distance = MinDistance(BoxSamples(a, rng, 400), BoxSamples(b, rng, 400), motion);
    const double bound = OrientedPairLowerBound(a, b, motion);
    EXPECT_LE(bound, distance + 1e-12) << "trial " << trial;
    // Stopping at a target returns a bound too (at least the target when it reaches it).
    const double stopped = OrientedPairLowerBound(a, b, motion, 0.5 * bound);
    EXPECT_LE(stopped, distance + 1e-12);
    EXPECT_GE(stopped, 0.5 * bound - 1e-12);
    positive += bound > 0.0;
  }
  EXPECT_GT(positive, 100);  // the test exercises separated boxes too
}

TEST(PairBounds, ThinFacingBoxesAreBoundedClosely) {
  // Two flat squares 0.1 apart, one turned about the normal: the gap.
  const std::vector<double> square = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  const OrientedBounds a = Fit(square);
  const OrientedBounds b = Fit(square);
  kernels::RigidMotion motion;
  const double c = std::cos(0.3), s = std::sin(0.3);
  const double r[3][3] = {{c, -s, 0}, {s, c, 0}, {0, 0, 1}};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) motion.rotation[i][j] = r[i][j];
  }
  motion.translation[0] = 0.2;
  motion.translation[2] = 0.1;
  EXPECT_NEAR(OrientedPairLowerBound(a, b, motion), 0.1, 1e-9);
  // The axis-aligned boxes of these untilted squares see the same gap.
  const BoxPairBound boxes(motion);
  const double lo[3] = {-1, -1, 0}, hi[3] = {1, 1, 0};
  EXPECT_NEAR(boxes.LowerBound(lo, hi, lo, hi), 0.1, 1e-9);
}

TEST(PairBounds, BoxLowerBoundNeverExceedsTheDistance) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 300; ++trial) {
    double loA[3], hiA[3], loB[3], hiB[3];
    for (int k = 0; k < 3; ++k) {
      loA[k] = u(rng);
      hiA[k] = loA[k] + std::abs(u(rng));
      loB[k] = u(rng);
      hiB[k] = loB[k] + std::abs(u(rng));
    }
    const kernels::RigidMotion motion = RandomMotion(rng, 2.0);
    auto samples = [&](const double* lo, const double* hi) {
      std::vector<double> points;
      for (int i = 0; i < 600; ++i) {
        double c[3] = {0.5 + 0.5 * u(rng), 0.5 + 0.5 * u(rng), 0.5 + 0.5 * u(rng)};
        c[i % 3] = i % 2 ? 0.0 : 1.0;
        for (int k = 0; k < 3; ++k) points.push_back(lo[k] + c[k] * (hi[k] - lo[k]));
      }
      return points;
    };
    const double distance = MinDistance(samples(loA, hiA), samples(loB, hiB), motion);
    EXPECT_LE(BoxPairBound(motion).LowerBound(loA, hiA, loB, hiB), distance + 1e-12) << "trial " << trial;
  }
}

TEST(PairBounds, SimplexPlaneGapNeverExceedsTheDistance) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int tight = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const int dimA = 1 + trial % 2, dimB = 1 + (trial / 2) % 2;
    double a[3][3], b[3][3];
    const double lift = 0.5 * u(rng);
    for (int v = 0; v < 3; ++v) {
      for (int k = 0; k < 3; ++k) {
        a[v][k] = u(rng);
        b[v][k] = u(rng);
      }
      // Every fourth pair nearly parallel triangles across a gap.
      if (trial % 4 == 3) {
        a[v][2] = 0.01 * u(rng);
        b[v][2] = lift + 0.01 * u(rng);
      }
    }
    const double* pa[3] = {a[0], a[1], a[2]};
    const double* pb[3] = {b[0], b[1], b[2]};
    double refA[3], refB[3], pointA[3], pointB[3];
    const double distance =
        std::sqrt(kernels::ClosestPointsOfSimplices(dimA, pa, dimB, pb, 3, refA, refB, pointA, pointB));
    const double gap = kernels::SimplexPlaneGap(dimA, pa, dimB, pb, 3);
    EXPECT_LE(gap, distance + 1e-12) << "trial " << trial;
    if (trial % 4 == 3 && dimA == 2 && dimB == 2 && distance > 0.05) tight += gap > 0.5 * distance;
  }
  EXPECT_GT(tight, 50);
}

TEST(PairBounds, TriangleClosedFormMatchesTheReference) {
  std::mt19937_64 rng(19);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int crossing = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    double a[3][3], b[3][3];
    const double shift = trial % 3 == 0 ? 0.0 : 1.5 * u(rng);  // a third may cross
    for (int v = 0; v < 3; ++v) {
      for (int k = 0; k < 3; ++k) {
        a[v][k] = u(rng);
        b[v][k] = u(rng) + (k == 2 ? shift : 0.0);
      }
    }
    const double* pa[3] = {a[0], a[1], a[2]};
    const double* pb[3] = {b[0], b[1], b[2]};
    double refA[3], refB[3], pointA[3], pointB[3];
    const double d2 = kernels::ClosestPointsOfSimplices(2, pa, 2, pb, 3, refA, refB, pointA, pointB);
    const double reference = testing::TriangleTriangleDistance(a[0], a[1], a[2], b[0], b[1], b[2]);
    EXPECT_NEAR(std::sqrt(d2), reference, 1e-12) << "trial " << trial;
    // The points are on their triangles, at that distance.
    for (int side = 0; side < 2; ++side) {
      const double* ref = side == 0 ? refA : refB;
      EXPECT_GE(ref[0], 0.0);
      EXPECT_GE(ref[1], 0.0);
      EXPECT_LE(ref[0] + ref[1], 1.0 + 1e-15);
    }
    double gap2 = 0.0;
    for (int k = 0; k < 3; ++k) gap2 += (pointA[k] - pointB[k]) * (pointA[k] - pointB[k]);
    EXPECT_NEAR(std::sqrt(gap2), reference, 1e-12);
    crossing += reference == 0.0;
  }
  EXPECT_GT(crossing, 100);
}

TEST(PairBounds, TriangleClosedFormOfFacingAndPlanarPairs) {
  // Mesh-like pairs (small triangles on nearly parallel planes, a vertex
  // over a face or an edge over an edge) and coplanar ones (2D), where the
  // closed form's quick answers apply or must not.
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 3000; ++trial) {
    const bool planar = trial % 4 == 0;
    const double gap = planar ? 0.0 : 0.3 * std::abs(u(rng));
    double a[3][3], b[3][3];
    for (int v = 0; v < 3; ++v) {
      a[v][0] = u(rng);
      a[v][1] = u(rng);
      a[v][2] = planar ? 0.0 : 0.05 * u(rng);
      b[v][0] = 0.8 * u(rng) + 0.5 * u(rng);
      b[v][1] = 0.8 * u(rng);
      b[v][2] = planar ? 0.0 : gap + 0.05 * u(rng);
    }
    const double* pa[3] = {a[0], a[1], a[2]};
    const double* pb[3] = {b[0], b[1], b[2]};
    double refA[3], refB[3], pointA[3], pointB[3];
    const int ambient = planar ? 2 : 3;
    const double d2 = kernels::ClosestPointsOfSimplices(2, pa, 2, pb, ambient, refA, refB, pointA, pointB);
    const double reference = testing::TriangleTriangleDistance(a[0], a[1], a[2], b[0], b[1], b[2]);
    EXPECT_NEAR(std::sqrt(d2), reference, 1e-12) << "trial " << trial;
    double gap2 = 0.0;
    for (int k = 0; k < ambient; ++k) gap2 += (pointA[k] - pointB[k]) * (pointA[k] - pointB[k]);
    EXPECT_NEAR(std::sqrt(gap2), reference, 1e-12) << "trial " << trial;
  }
}

}  // namespace
}  // namespace invmap::engine
