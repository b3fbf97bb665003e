// PointTracker: every update against Manifold::Invert of the same point
// (the same record: status, distance, a closest point on the geometry at
// the reported cell and parameters), along paths of small steps with jumps
// to other parts of the geometry, on surfaces, a triangle mesh, a torus and
// a volume mesh; invalid points and max distance; moved-from trackers.
#include <gtest/gtest.h>

#include <random>

#include "tests/distance/distance_test_util.h"
#include "tests/support/distance_geometries.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

void FollowPath(const Geometry& geometry, const std::array<double, 3>& start, double step, int count,
                double maxDistance = std::numeric_limits<double>::infinity()) {
  const auto model = BuildModel(geometry);
  const double size = GeometrySize(geometry);
  const int dim = geometry.dimension;
  PointTracker tracker(model->manifold, maxDistance);
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double lo[3], hi[3];
  GeometryControlBox(geometry, lo, hi);
  std::array<double, 3> p = start;
  InversionOptions options;
  options.maxDistance = maxDistance;
  for (int i = 0; i < count; ++i) {
    if (i % 25 == 24) {
      // A jump to anywhere in (and around) the box.
      for (int k = 0; k < dim; ++k) p[k] = lo[k] + (hi[k] - lo[k]) * (0.5 + 0.7 * u(rng));
    } else {
      for (int k = 0; k < dim; ++k) p[k] += step * size * u(rng);
    }
    PointAnswer tracked;
    std::string message;
    ASSERT_EQ(tracker.Update(p.data(), &tracked, &message), Error::Ok) << message;
    Results fresh;
    ASSERT_EQ(model->manifold.Invert(PointsView::Interleaved(p.data(), 1, dim), options, &fresh), Error::Ok);
    SCOPED_TRACE("step " + std::to_string(i));
    ASSERT_EQ(tracked.status, fresh.status[0]);
    if (tracked.status != Status::Found) continue;
    EXPECT_NEAR(tracked.distance, fresh.distance[0], 1e-11 * size);
    // The reported point is the geometry's at the reported cell and params.
    double x[3] = {0, 0, 0};
    ASSERT_EQ(EvaluateReported(geometry, tracked.patch, tracked.cell, tracked.params, 1e-9, x), "");
    EXPECT_LE(PointDistance(x, tracked.closest), 1e-9 * size);
    EXPECT_NEAR(PointDistance(p.data(), tracked.closest), tracked.distance, 1e-11 * size);
  }
}

TEST(PointTracker, BicubicSurface) {
  FollowPath(WavySurface(0.08, 2, 2, 16, false), {0.3, 0.4, 0.1}, 0.003, 120);
}

TEST(PointTracker, TriangleMesh) {
  FollowPath(MeshGeometry(BumpySphereMesh(48, 32, {0, 0, 0}, 1.0)), {0.2, 0.9, 0.3}, 0.002, 120);
}

TEST(PointTracker, TorusAndMaxDistance) {
  FollowPath(NurbsTorus({0, 0, 0}, 2.0, 0.7), {2.5, 0.3, 0.9}, 0.01, 80, 0.5);
}

TEST(PointTracker, VolumeMesh) {
  // Quadratic tets: inside points are at distance 0 with their preimage.
  FollowPath(QuadraticMesh(false), {0.5, 0.5, 0.5}, 0.01, 60);
}

TEST(PointTracker, InvalidPointsAndEmptyAnswers) {
  const auto model = BuildModel(NurbsSphere({0, 0, 0}, 1.0));
  PointTracker tracker(model->manifold, 0.5);
  PointAnswer answer;
  const double nan[3] = {std::nan(""), 0, 0};
  ASSERT_EQ(tracker.Update(nan, &answer), Error::Ok);
  EXPECT_EQ(answer.status, Status::Invalid);
  const double far[3] = {3, 0, 0};
  ASSERT_EQ(tracker.Update(far, &answer), Error::Ok);
  EXPECT_EQ(answer.status, Status::None);
  EXPECT_EQ(answer.patch, -1);
  const double near[3] = {1.2, 0, 0};
  ASSERT_EQ(tracker.Update(near, &answer), Error::Ok);
  EXPECT_EQ(answer.status, Status::Found);
  EXPECT_NEAR(answer.distance, 0.2, 1e-12);
}

TEST(Trackers, MovedFromTrackersAnswerAnError) {
  // As a moved-from Manifold does: an error and a message, not a crash.
  const auto model = BuildModel(NurbsSphere({0, 0, 0}, 1.0));
  std::string message;
  PointTracker point(model->manifold);
  PointTracker pointMoved(std::move(point));
  PointAnswer answer;
  const double p[3] = {1.5, 0, 0};
  EXPECT_EQ(point.Update(p, &answer, &message), Error::InvalidArgument);  // NOLINT(bugprone-use-after-move)
  EXPECT_NE(message.find("moved from"), std::string::npos) << message;
  EXPECT_EQ(pointMoved.Update(p, &answer), Error::Ok);
  EXPECT_NEAR(answer.distance, 0.5, 1e-12);

  DistanceTracker pair(model->model, model->model);
  DistanceTracker pairMoved(std::move(pair));
  DistanceResult result;
  message.clear();
  EXPECT_EQ(pair.Update(Pose(), &result, &message), Error::InvalidArgument);  // NOLINT(bugprone-use-after-move)
  EXPECT_NE(message.find("moved from"), std::string::npos) << message;
  EXPECT_EQ(pair.SetPoseA(Pose(), &message), Error::InvalidArgument);  // NOLINT(bugprone-use-after-move)
  EXPECT_EQ(pairMoved.Update(Pose(), &result), Error::Ok);
  EXPECT_TRUE(result.nearest.found);
  EXPECT_EQ(result.nearest.distance, 0.0);
}

}  // namespace
}  // namespace invmap::testing
