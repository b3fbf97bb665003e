// Shared helpers of the distance tests: building models, poses, and the
// check that a reported point is its model's point at the reported cell and
// parameters (evaluated by the tests' own patch reader), moved by the pose.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "invmap/distance.h"
#include "invmap/invmap.h"
#include "tests/support/pair_reference.h"
#include "tests/support/patch_reference.h"

namespace invmap::testing {

/// A manifold and its distance model (which refers to it: kept together, never moved).
struct BuiltModel {
  Geometry geometry;
  Manifold manifold;
  DistanceModel model;
};

inline std::unique_ptr<BuiltModel> BuildModel(const Geometry& geometry) {
  auto built = std::make_unique<BuiltModel>();
  built->geometry = geometry;
  BuildResult result = Manifold::Build(geometry);
  EXPECT_EQ(result.error, "");
  built->manifold = std::move(result.manifold);
  DistanceModelBuild model = DistanceModel::Build(built->manifold);
  EXPECT_EQ(model.error, "");
  built->model = model.model;
  return built;
}

inline Pose ToPose(const PoseRows& rows) { return Pose::FromRows(rows.data()); }

/// The distance between two points (3 coordinates).
inline double PointDistance(const double* a, const double* b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

/// "" when `point` is geometry's point at its patch, cell and params moved
/// by `pose` (within tol), else why not.
inline std::string CheckOnModel(const Geometry& geometry, const PoseRows& pose, const ModelPoint& point, double tol) {
  double x[3] = {0, 0, 0};
  const std::string error = EvaluateReported(geometry, point.patch, point.cell, point.params, 1e-9, x);
  if (!error.empty()) return error;
  double world[3];
  ApplyRows(pose, x, world);
  const double gap = PointDistance(world, point.point);
  if (!(gap <= tol)) return "the reported point is " + std::to_string(gap) + " from the model's point at its params";
  return "";
}

/// Distance between the models under the poses, asserting success.
inline DistanceResult DistanceQuery(const BuiltModel& a, const PoseRows& poseA, const BuiltModel& b, const PoseRows& poseB,
                            DistanceOptions options = {}) {
  DistanceResult result;
  std::string message;
  EXPECT_EQ(Distance(a.model, ToPose(poseA), b.model, ToPose(poseB), options, &result, &message), Error::Ok)
      << message;
  return result;
}

/// The checks every answer must pass: found, both points on their models
/// at their parameters, distance = |a - b|.
inline void ExpectConsistent(const BuiltModel& a, const PoseRows& poseA, const BuiltModel& b, const PoseRows& poseB,
                             const DistanceAnswer& answer, double tol) {
  ASSERT_TRUE(answer.found);
  EXPECT_EQ(CheckOnModel(a.geometry, poseA, answer.a, tol), "");
  EXPECT_EQ(CheckOnModel(b.geometry, poseB, answer.b, tol), "");
  EXPECT_NEAR(answer.distance, PointDistance(answer.a.point, answer.b.point), tol);
}

}  // namespace invmap::testing
