// Moving models: a DistanceTracker's answer for every pose of a trajectory
// (small steps, a jump to another part of the model, passes through
// contact) against a fresh query for that pose, and the tracker's errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "samples/sample_geometries.h"
#include "tests/distance/distance_test_util.h"
#include "tests/support/distance_geometries.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

/// Poses of B along a path: a wander over [0, 1]^2 at heights above the
/// surface, turning slowly, with a jump at `jumpAt` and a dip to contact.
std::vector<PoseRows> Trajectory(int count, int jumpAt, double height) {
  std::vector<PoseRows> poses;
  double x = 0.2, y = 0.3, z = height, angle = 0.0;
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < count; ++i) {
    if (i == jumpAt) {
      x = 0.85;
      y = 0.8;
    }
    x = std::clamp(x + 0.01 * u(rng), 0.05, 0.95);
    y = std::clamp(y + 0.01 * u(rng), 0.05, 0.95);
    // Down to touching and back up between the first third and half.
    z = i > count / 3 && i < count / 2 ? std::max(0.0, z - 0.02) : std::min(height, z + 0.02);
    angle += 0.05;
    poses.push_back(RotationRows({0.3, 0.2, 1.0}, angle, {x, y, z}));
  }
  return poses;
}

TEST(Trajectories, SphereOverASurfaceMatchesFreshQueries) {
  const auto surface = BuildModel(WavySurface(0.05, 2, 2, 12, false));
  const auto sphere = BuildModel(NurbsSphere({0, 0, 0}, 0.1));
  const std::vector<PoseRows> poses = Trajectory(30, 20, 0.25);
  DistanceTracker tracker(surface->model, sphere->model);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    DistanceResult tracked;
    std::string message;
    ASSERT_EQ(tracker.Update(ToPose(poses[i]), &tracked, &message), Error::Ok) << message;
    const DistanceResult fresh = DistanceQuery(*surface, IdentityRows(), *sphere, poses[i]);
    SCOPED_TRACE("pose " + std::to_string(i));
    ASSERT_TRUE(tracked.nearest.found);
    EXPECT_NEAR(tracked.nearest.distance, fresh.nearest.distance, 1e-10);
    EXPECT_EQ(tracked.nearest.certified, true);
    ExpectConsistent(*surface, IdentityRows(), *sphere, poses[i], tracked.nearest, 1e-9);
  }
}

TEST(Trajectories, MeshAgainstMeshMatchesFreshQueries) {
  const auto big = BuildModel(MeshGeometry(WavyHeightField(24, 3)));
  const auto probe = BuildModel(MeshGeometry(BumpySphereMesh(10, 7, {0, 0, 0}, 0.08)));
  const std::vector<PoseRows> poses = Trajectory(60, 25, 0.3);
  DistanceTracker tracker(big->model, probe->model);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    DistanceResult tracked;
    ASSERT_EQ(tracker.Update(ToPose(poses[i]), &tracked), Error::Ok);
    const DistanceResult fresh = DistanceQuery(*big, IdentityRows(), *probe, poses[i]);
    SCOPED_TRACE("pose " + std::to_string(i));
    EXPECT_NEAR(tracked.nearest.distance, fresh.nearest.distance, 1e-12);
    ExpectConsistent(*big, IdentityRows(), *probe, poses[i], tracked.nearest, 1e-12);
  }
}

/// Poses of B in small steps (what a tracker keeps between poses lets it
/// skip most pairs then), with jumps to other parts of A at `jumps`: a
/// wander at a height that dips toward A now and then.
std::vector<PoseRows> SmallSteps(int count, const std::vector<int>& jumps, double height, double step) {
  std::vector<PoseRows> poses;
  double x = 0.3, y = 0.4, angle = 0.0;
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0), place(0.1, 0.9);
  for (int i = 0; i < count; ++i) {
    if (std::find(jumps.begin(), jumps.end(), i) != jumps.end()) {
      x = place(rng);
      y = place(rng);
      angle += 2.0;
    }
    x = std::clamp(x + step * u(rng), 0.05, 0.95);
    y = std::clamp(y + step * u(rng), 0.05, 0.95);
    angle += 10.0 * step;
    const double z = height * (0.8 + 0.2 * std::cos(0.05 * i));
    poses.push_back(RotationRows({0.3, 0.2, 1.0}, angle, {x, y, z}));
  }
  return poses;
}

/// The tracker over `poses` against a fresh query per pose; A moves once, at `moveAAt`.
void TrackAgainstFresh(const BuiltModel& a, const BuiltModel& b, const std::vector<PoseRows>& poses, int moveAAt,
                       double tol) {
  DistanceTracker tracker(a.model, b.model);
  PoseRows poseA = IdentityRows();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (static_cast<int>(i) == moveAAt) {
      poseA = RotationRows({0, 0, 1}, 0.01, {0.002, -0.001, 0.003});
      ASSERT_EQ(tracker.SetPoseA(ToPose(poseA)), Error::Ok);
    }
    DistanceResult tracked;
    std::string message;
    ASSERT_EQ(tracker.Update(ToPose(poses[i]), &tracked, &message), Error::Ok) << message;
    const DistanceResult fresh = DistanceQuery(a, poseA, b, poses[i]);
    SCOPED_TRACE("pose " + std::to_string(i));
    ASSERT_TRUE(tracked.nearest.found);
    EXPECT_NEAR(tracked.nearest.distance, fresh.nearest.distance, tol);
    EXPECT_TRUE(tracked.nearest.certified) << "fresh certified " << fresh.nearest.certified << " distance " << fresh.nearest.distance;
    ExpectConsistent(a, poseA, b, poses[i], tracked.nearest, tol);
  }
}

TEST(Trajectories, SmallStepsAndJumpsOverASurfaceMatchFreshQueries) {
  const auto surface = BuildModel(WavySurface(0.05, 2, 2, 12, false));
  const auto sphere = BuildModel(NurbsSphere({0, 0, 0}, 0.1));
  TrackAgainstFresh(*surface, *sphere, SmallSteps(50, {20, 21, 40}, 0.3, 1e-3), 30, 1e-9);
}

TEST(Trajectories, SmallStepsAndJumpsOverAMeshMatchFreshQueries) {
  const auto big = BuildModel(MeshGeometry(WavyHeightField(24, 3)));
  const auto probe = BuildModel(MeshGeometry(BumpySphereMesh(10, 7, {0, 0, 0}, 0.08)));
  TrackAgainstFresh(*big, *probe, SmallSteps(200, {70, 71, 140}, 0.35, 1e-3), 100, 1e-12);
}

TEST(Trajectories, FlatTorusOverABumpySurfaceMatchesFreshQueries) {
  // The benchmark's case (bench_distance's BM_DistanceTrackerSurfaces,
  // fewer cells): a flat torus's lowest points lie on the edge between two
  // of its cells, and over a bump of the surface near the surface cells'
  // edges, so several pairs tie within a step of the answer at every pose
  // and are searched from their kept partitions (kernels::PairPartition).
  const auto surface = BuildModel(samples::WavySurface(16));
  const auto torus = BuildModel(samples::NurbsTorus(0.1, 0.04));
  std::vector<PoseRows> poses;
  double x = 0.55, y = 0.7, angle = 0.0;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0), place(0.2, 0.8);
  for (int i = 0; i < 80; ++i) {
    if (i == 30 || i == 55) {
      x = place(rng);
      y = place(rng);
      angle += 1.0;
    }
    x += 3e-4 * u(rng);
    y += 3e-4 * u(rng);
    angle += 1e-3;
    poses.push_back(RotationRows({0, 0, 1}, angle, {x, y, 0.25}));
  }
  TrackAgainstFresh(*surface, *torus, poses, 70, 1e-9);
}

TEST(Trajectories, MovingATooAndBadPoses) {
  const auto a = BuildModel(NurbsSphere({0, 0, 0}, 1.0));
  const auto b = BuildModel(NurbsSphere({0, 0, 0}, 0.5));
  DistanceTracker tracker(a->model, b->model);
  DistanceResult r;
  ASSERT_EQ(tracker.Update(ToPose(RotationRows({0, 0, 1}, 0.0, {3, 0, 0})), &r), Error::Ok);
  EXPECT_NEAR(r.nearest.distance, 1.5, 1e-9);
  ASSERT_EQ(tracker.SetPoseA(ToPose(RotationRows({0, 0, 1}, 0.0, {0.5, 0, 0}))), Error::Ok);
  ASSERT_EQ(tracker.Update(ToPose(RotationRows({0, 0, 1}, 0.0, {3, 0, 0})), &r), Error::Ok);
  EXPECT_NEAR(r.nearest.distance, 1.0, 1e-9);
  // A scaling is no rigid motion; the tracker stays usable.
  Pose scaled = ToPose(IdentityRows());
  scaled.m[0] = scaled.m[5] = scaled.m[10] = 2.0;
  std::string message;
  EXPECT_EQ(tracker.Update(scaled, &r, &message), Error::InvalidArgument);
  EXPECT_NE(message.find("rotation"), std::string::npos) << message;
  ASSERT_EQ(tracker.Update(ToPose(RotationRows({0, 0, 1}, 0.0, {-3, 0, 0})), &r), Error::Ok);
  EXPECT_NEAR(r.nearest.distance, 2.0, 1e-9);
}

}  // namespace
}  // namespace invmap::testing
