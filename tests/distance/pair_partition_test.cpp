// A tracked pair search (kernels::PairPartition: the search starts from
// the subdomains the last motion's search left, skipping those whose bound
// the drift has not used up) against a fresh search of the same pair at
// every motion, and against dense sampling of both cells: random curved
// cells, B moving in small steps with jumps, searched without a bound, under
// one it cannot beat and under one it just beats. And the bound of how much
// nearer two moved boxes of points can have come (kernels/pair_motion_bound.h)
// against every pair of points of two random clouds.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "engine/pair_bound_cache.h"
#include "engine/pair_bounds.h"
#include "kernels/pair_motion_bound.h"
#include "kernels/pair_search.h"
#include "tests/distance/pair_case.h"
#include "tests/support/reference_cell.h"

namespace invmap::kernels {
namespace {

using testing::RandomCurvedCell;

double SampledDistance(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
  double best = 1e300;
  for (const Eigen::Vector3d& p : a) {
    for (const Eigen::Vector3d& q : b) best = std::min(best, (p - q).norm());
  }
  return best;
}

/// B's motion a small step (or, with `jump`, a large one) from `m`.
RigidMotion Step(const RigidMotion& m, std::mt19937_64& rng, bool jump) {
  return jump ? StepMotion(m, rng, 2.0, 0.5) : StepMotion(m, rng, 2e-3, 2e-3);
}

/// The largest distance of B's control points from its own origin (what
/// the drift's radius must bound).
double ControlRadius(const testing::RefCell& cell) {
  double r2 = 0.0;
  for (int c = 0; c < cell.numControlPoints(); ++c) {
    double d2 = 0.0;
    for (int k = 0; k < cell.ambientDim; ++k) d2 += cell.points[c * cell.ambientDim + k] * cell.points[c * cell.ambientDim + k];
    r2 = std::max(r2, d2);
  }
  return std::sqrt(r2) * (1.0 + 1e-15);
}

TEST(PairPartition, MotionBoundHoldsForEveryPairOfPoints) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    // Two clouds of points in their own frames, of random sizes.
    std::vector<Eigen::Vector3d> local[2];
    for (int s = 0; s < 2; ++s) {
      const double spread = 0.05 + std::abs(u(rng));
      const Eigen::Vector3d center(u(rng), u(rng), u(rng));
      for (int i = 0; i < 40; ++i) local[s].push_back(center + spread * Eigen::Vector3d(u(rng), u(rng), u(rng)));
    }
    RigidMotion then[2] = {RandomMotion(rng, 3), RandomMotion(rng, 3)};
    RigidMotion now[2] = {Step(then[0], rng, trial % 5 == 0), Step(then[1], rng, trial % 7 == 0)};
    std::vector<Eigen::Vector3d> before[2], after[2];
    double lo[2][3], hi[2][3];
    for (int s = 0; s < 2; ++s) {
      for (int k = 0; k < 3; ++k) {
        lo[s][k] = 1e300;
        hi[s][k] = -1e300;
      }
      for (const Eigen::Vector3d& p : local[s]) {
        double x[3], y[3];
        then[s].Apply(p.data(), x);
        now[s].Apply(p.data(), y);
        before[s].emplace_back(x[0], x[1], x[2]);
        after[s].emplace_back(y[0], y[1], y[2]);
        for (int k = 0; k < 3; ++k) {
          lo[s][k] = std::min(lo[s][k], x[k]);
          hi[s][k] = std::max(hi[s][k], x[k]);
        }
      }
    }
    double place[kSubdomainPlaceSize];
    WriteSubdomainPlace(lo, hi, then[0], then[1], place);
    const double change = SquaredDistanceChangeBound(place, now[0], now[1]);
    for (std::size_t i = 0; i < before[0].size(); ++i) {
      for (std::size_t j = 0; j < before[1].size(); ++j) {
        const double was = (before[0][i] - before[1][j]).squaredNorm();
        const double is = (after[0][i] - after[1][j]).squaredNorm();
        ASSERT_GE(is - was, change) << "trial " << trial;
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 200 * 40 * 40);
}

TEST(PairPartition, MotionBoundChargesLittleForASlideAcrossTheGap) {
  // Boxes of 0.2 a unit apart along z, B sliding 1e-3 along x: its points
  // move by 1e-3, which the drift charges in full (a squared distance down
  // by 2e-3); across the gap the distance barely changes.
  const double lo[2][3] = {{-0.1, -0.1, -0.1}, {-0.1, -0.1, 0.9}};
  const double hi[2][3] = {{0.1, 0.1, 0.1}, {0.1, 0.1, 1.1}};
  RigidMotion a, b, moved;
  moved.translation[0] = 1e-3;
  double place[kSubdomainPlaceSize];
  WriteSubdomainPlace(lo, hi, a, b, place);
  const double change = SquaredDistanceChangeBound(place, a, moved);
  EXPECT_LE(change, 0.0);
  EXPECT_GE(change, -2.0 * 0.4 * 1e-3 * 1.0001);
  // No motion: no change but the rounding's allowance.
  EXPECT_LE(SquaredDistanceChangeBound(place, a, b), 0.0);
  EXPECT_GE(SquaredDistanceChangeBound(place, a, b), -1e-12);
}

TEST(PairPartition, TrackedSearchesMatchFreshOnesAndDenseSampling) {
  const CellType types[] = {CellType::Line, CellType::Quad, CellType::Tri};
  std::mt19937_64 rng(41);
  std::uniform_int_distribution<int> degree(2, 3);
  PairWorkspace ws;
  int poses = 0, reused = 0;
  for (int trial = 0; trial < 12; ++trial) {
    PairCase pair;
    const CellType ta = types[trial % 3], tb = types[(trial / 3) % 3];
    const bool rational = trial % 2 == 0;
    pair.cell[0] = RandomCurvedCell(ta, degree(rng), rational, 3, rng);
    pair.cell[1] = RandomCurvedCell(tb, degree(rng), !rational, 3, rng);
    BuildSide(pair.cell[0], RandomMotion(rng, 3), &pair.nets[0], &pair.side[0]);
    RigidMotion motionB = RandomMotion(rng, 3);
    BuildSide(pair.cell[1], motionB, &pair.nets[1], &pair.side[1]);
    const double size = std::max(pair.cell[0].size(), pair.cell[1].size());
    const auto samplesA = Samples(pair.cell[0], pair.side[0].motion, 16);
    engine::PairBoundCache drift;
    drift.SetRadius(ControlRadius(pair.cell[1]));
    PairPartition kept, next;
    for (int pose = 0; pose < 40; ++pose) {
      SCOPED_TRACE("trial " + std::to_string(trial) + " pose " + std::to_string(pose));
      if (pose > 0) motionB = Step(motionB, rng, pose % 15 == 0);
      pair.side[1].motion = motionB;
      drift.MoveTo(engine::RelativeMotion(pair.side[0].motion, motionB));
      const PairSolveResult fresh = SolveCellPair(pair.side[0], pair.side[1], nullptr, nullptr, &ws);
      ASSERT_NE(fresh.status, PairStatus::NotCertified);
      // No bound, a bound the pair cannot beat, a bound it just beats.
      const int kind = pose % 3;
      const double bound2 = kind == 0   ? std::numeric_limits<double>::infinity()
                            : kind == 1 ? std::pow(fresh.distance * (1.0 - 1e-3) - 1e-9, 2)
                                        : std::pow(fresh.distance * (1.0 + 1e-6) + 1e-9, 2);
      const bool fromKept = kept.valid;
      reused += fromKept ? 1 : 0;
      const PairReuse reuse{&kept, &next, drift.drift()};
      const PairSolveResult tracked = SolveCellPair(pair.side[0], pair.side[1], nullptr, nullptr, &ws, bound2, &reuse);
      std::swap(kept, next);
      ++poses;
      const double sampled = SampledDistance(samplesA, Samples(pair.cell[1], motionB, 16));
      // Never above the distance: the bound a tracker keeps.
      EXPECT_LE(tracked.lowerBound, sampled + 1e-9 * size);
      ASSERT_NE(tracked.status, PairStatus::NotCertified);
      if (kind == 1) {
        EXPECT_EQ(tracked.status, PairStatus::Farther);
        continue;
      }
      EXPECT_NE(tracked.status, PairStatus::Farther);
      EXPECT_NEAR(tracked.distance, fresh.distance, 1e-9 * size);
      EXPECT_LE(tracked.distance, sampled + 1e-9 * size);
      EXPECT_NEAR(tracked.lowerBound, tracked.distance, 1e-9 * size);
    }
  }
  // The partitions were used: most poses after the first of each pair.
  EXPECT_GT(reused, poses / 2);
}

}  // namespace
}  // namespace invmap::kernels
