// What a tracker keeps between poses (engine/pair_bound_cache.h): the drift
// it sums bounds how far every point of B has moved since any earlier pose
// (random walks of small steps, turns and jumps, points anywhere within
// B's radius), a kept bound excludes a pair only while the drift has not
// used it up, and pairs are told apart.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "engine/pair_bound_cache.h"
#include "tests/distance/pair_case.h"

namespace invmap::engine {
namespace {

TEST(PairBoundCache, DriftBoundsEveryPointsMotionSinceAnyPose) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double radius = 2.5;
  // Points of B within its radius, some on the sphere of that radius.
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 200; ++i) {
    Eigen::Vector3d y(u(rng), u(rng), u(rng));
    y = y.normalized() * radius * (i % 2 ? 1.0 : std::abs(u(rng)));
    points.push_back(y);
  }
  PairBoundCache cache;
  cache.SetRadius(radius);
  std::vector<kernels::RigidMotion> motions{kernels::RandomMotion(rng, 3)};
  std::vector<double> drifts;
  cache.MoveTo(motions[0]);
  drifts.push_back(cache.drift());
  int tight = 0;
  for (int pose = 1; pose < 300; ++pose) {
    // Mostly small steps; now and then a jump.
    const bool jump = pose % 50 == 0;
    motions.push_back(kernels::StepMotion(motions.back(), rng, jump ? 3.0 : 1e-3, jump ? 2.0 : 1e-3));
    cache.MoveTo(motions.back());
    drifts.push_back(cache.drift());
    for (std::size_t earlier = 0; earlier < motions.size(); earlier += 7) {
      double moved = 0.0;
      for (const Eigen::Vector3d& y : points) {
        double p[3], q[3];
        motions[earlier].Apply(y.data(), p);
        motions.back().Apply(y.data(), q);
        moved = std::max(moved, std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]));
      }
      const double drift = drifts.back() - drifts[earlier];
      ASSERT_GE(drift, moved) << "pose " << pose << " since " << earlier;
      if (earlier + 1 == motions.size() - 1 && drift < 3.0 * moved) ++tight;
    }
  }
  // One step's drift is within a small factor of the farthest point's move.
  EXPECT_GT(tight, 0);
}

TEST(PairBoundCache, ExcludesAPairWhileItsBoundLasts) {
  PairBoundCache cache;
  cache.SetRadius(1.0);
  kernels::RigidMotion m;
  cache.MoveTo(m);
  EXPECT_FALSE(cache.Excludes(3, 4, 0.5));  // nothing kept yet
  cache.Record(3, 4, 1.0);
  cache.Record(3, 4, 0.7);  // a weaker proof at the same motion changes nothing
  EXPECT_TRUE(cache.Excludes(3, 4, 0.99));
  EXPECT_FALSE(cache.Excludes(3, 4, 1.01));
  EXPECT_FALSE(cache.Excludes(4, 3, 0.5));  // the pair the other way round is another pair
  // B moves by 0.1: the pair may have come 0.1 nearer.
  m.translation[0] = 0.1;
  cache.MoveTo(m);
  EXPECT_TRUE(cache.Excludes(3, 4, 0.89));
  EXPECT_FALSE(cache.Excludes(3, 4, 0.91));
  // A fresh proof replaces it.
  cache.Record(3, 4, 0.5);
  EXPECT_FALSE(cache.Excludes(3, 4, 0.51));
  // Many pairs: the table grows and keeps them all.
  for (std::int64_t i = 0; i < 5000; ++i) cache.Record(i, i + 1, 2.0 + static_cast<double>(i));
  for (std::int64_t i = 0; i < 5000; i += 97) {
    EXPECT_TRUE(cache.Excludes(i, i + 1, 1.9 + static_cast<double>(i)));
    EXPECT_FALSE(cache.Excludes(i, i + 1, 2.1 + static_cast<double>(i)));
  }
  cache.Clear();
  EXPECT_FALSE(cache.Excludes(0, 1, 0.0));
}

}  // namespace
}  // namespace invmap::engine
