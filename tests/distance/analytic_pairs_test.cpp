// Model-to-model distances with answers known in closed form: spheres,
// a sphere and a torus, crossed and parallel cylinders, segments, a curve
// touching a surface, and models that overlap (distance 0, a common point).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "samples/sample_geometries.h"
#include "tests/distance/distance_test_util.h"
#include "tests/support/distance_geometries.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

constexpr double kTol = 1e-9;
constexpr double kPi = 3.14159265358979323846;

double Norm(const std::array<double, 3>& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

TEST(AnalyticPairs, SphereAndSphereUnderRandomPoses) {
  const auto a = BuildModel(NurbsSphere({0, 0, 0}, 1.0));
  const auto b = BuildModel(NurbsSphere({0, 0, 0}, 0.5));
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 12; ++trial) {
    const std::array<double, 3> axis{u(rng), u(rng), u(rng)};
    std::array<double, 3> t{u(rng), u(rng), u(rng)};
    const double scale = (1.7 + 1.5 * std::abs(u(rng))) / Norm(t);
    for (double& x : t) x *= scale;
    const PoseRows poseB = RotationRows(axis, 3.0 * u(rng), t);
    const PoseRows poseA = RotationRows({u(rng), u(rng), u(rng)}, u(rng), {0, 0, 0});
    const DistanceResult r = DistanceQuery(*a, poseA, *b, poseB);
    const double expected = Norm(t) - 1.5;
    EXPECT_NEAR(r.nearest.distance, expected, kTol) << "trial " << trial;
    EXPECT_TRUE(r.nearest.certified);
    ExpectConsistent(*a, poseA, *b, poseB, r.nearest, 1e-9);
    // The points lie on the line of centres.
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(r.nearest.a.point[k], t[k] / Norm(t), 1e-7);
      EXPECT_NEAR(r.nearest.b.point[k], t[k] * (1.0 - 0.5 / Norm(t)), 1e-7);
    }
  }
}

TEST(AnalyticPairs, OverlappingSpheresAreAtZeroWithACommonPoint) {
  const auto a = BuildModel(NurbsSphere({0, 0, 0}, 1.0));
  const auto b = BuildModel(NurbsSphere({0, 0, 0}, 0.5));
  for (const double offset : {1.2, 0.9, 0.6, 1.5}) {
    const PoseRows poseB = RotationRows({0, 1, 1}, 0.4, {offset * 0.6, offset * 0.8, 0.0});
    const DistanceResult r = DistanceQuery(*a, IdentityRows(), *b, poseB);
    ASSERT_TRUE(r.nearest.found);
    EXPECT_EQ(r.nearest.distance, 0.0) << "offset " << offset;
    ExpectConsistent(*a, IdentityRows(), *b, poseB, r.nearest, 1e-9);
    // The common point lies on both spheres.
    const double c[3] = {offset * 0.6, offset * 0.8, 0.0};
    const double origin[3] = {0, 0, 0};
    EXPECT_NEAR(PointDistance(r.nearest.a.point, origin), 1.0, 1e-9);
    EXPECT_NEAR(PointDistance(r.nearest.a.point, c), 0.5, 1e-9);
  }
}

TEST(AnalyticPairs, SphereAndTorus) {
  const double big = 2.0, small = 0.7, radius = 0.3;
  const auto torus = BuildModel(NurbsTorus({0, 0, 0}, big, small));
  const auto sphere = BuildModel(NurbsSphere({0, 0, 0}, radius));
  // Centres outside the tube: one closest pair.
  const std::array<double, 3> centres[] = {{3.5, 0.4, 0.9}, {-1.2, 2.9, -1.1}, {1.4, -1.6, 0.2}};
  for (const auto& c : centres) {
    const PoseRows poseB = RotationRows({1, 2, 3}, 0.7, c);
    const DistanceResult r = DistanceQuery(*torus, IdentityRows(), *sphere, poseB);
    const double expected = TorusDistance({0, 0, 0}, big, small, c.data()) - radius;
    EXPECT_NEAR(r.nearest.distance, expected, kTol) << c[0] << " " << c[1] << " " << c[2];
    EXPECT_TRUE(r.nearest.certified) << c[0] << " " << c[1] << " " << c[2];
    ExpectConsistent(*torus, IdentityRows(), *sphere, poseB, r.nearest, 1e-9);
  }
  // Centres on the axis, and near it in the hole: the closest points form a
  // whole circle of the tube (or nearly). The distance is right; such a
  // valley of equal distances running across both models' parameters is
  // not always certified within the search's budget (docs/distance.md).
  const std::array<double, 3> onAxis[] = {{0.2, -0.3, 0.1}, {0, 0, 1.6}};
  for (const auto& c : onAxis) {
    const PoseRows poseB = RotationRows({1, 2, 3}, 0.7, c);
    const DistanceResult r = DistanceQuery(*torus, IdentityRows(), *sphere, poseB);
    const double expected = TorusDistance({0, 0, 0}, big, small, c.data()) - radius;
    EXPECT_NEAR(r.nearest.distance, expected, kTol) << c[0] << " " << c[1] << " " << c[2];
    ExpectConsistent(*torus, IdentityRows(), *sphere, poseB, r.nearest, 1e-9);
  }
}

TEST(AnalyticPairs, SurfaceInsideATorusHole) {
  // The wavy surface over [0, 1]^2 inside the hole of a torus around the
  // vertical line through (0.5, 0.5): its four corners (all at z = 0.125,
  // the farthest points from the axis) tie for the nearest. Seen from so
  // near the axis the torus's cells bend little along their arcs; the
  // search must still split them, not only the surface's corner cells.
  const auto surface = BuildModel(samples::WavySurface(8));
  const auto torus = BuildModel(samples::NurbsTorus(2.0, 0.7));
  const PoseRows poseB = RotationRows({0, 0, 1}, 0.0, {0.5, 0.5, 0.6});
  const DistanceResult r = DistanceQuery(*surface, IdentityRows(), *torus, poseB);
  const double corner[3] = {1.0, 1.0, 0.125};
  const double expected = TorusDistance({0.5, 0.5, 0.6}, 2.0, 0.7, corner);
  EXPECT_NEAR(r.nearest.distance, expected, kTol);
  EXPECT_TRUE(r.nearest.certified);
  EXPECT_NEAR(std::abs(r.nearest.a.point[0] - 0.5), 0.5, 1e-9);
  EXPECT_NEAR(std::abs(r.nearest.a.point[1] - 0.5), 0.5, 1e-9);
  ExpectConsistent(*surface, IdentityRows(), *torus, poseB, r.nearest, 1e-9);
}

TEST(AnalyticPairs, CrossedAndParallelCylinders) {
  const auto a = BuildModel(NurbsCylinder(0.5, 4.0));
  const auto b = BuildModel(NurbsCylinder(0.3, 4.0));
  for (const double gap : {0.05, 0.4, 1.3}) {
    const double axes = 0.8 + gap;
    // B's axis along x (a quarter turn about y), crossing A's above it.
    const PoseRows crossed = RotationRows({0, 1, 0}, kPi / 2, {0.2, axes, 0.3});
    const DistanceResult rc = DistanceQuery(*a, IdentityRows(), *b, crossed);
    EXPECT_NEAR(rc.nearest.distance, gap, kTol) << "crossed, gap " << gap;
    EXPECT_TRUE(rc.nearest.certified);
    ExpectConsistent(*a, IdentityRows(), *b, crossed, rc.nearest, 1e-9);
    // B's axis parallel to A's: the closest points form a segment (a valley
    // of equal distances: right, not always certified, as above).
    const PoseRows parallel = RotationRows({0, 0, 1}, 0.3, {axes * std::cos(0.6), axes * std::sin(0.6), 0.7});
    const DistanceResult rp = DistanceQuery(*a, IdentityRows(), *b, parallel);
    EXPECT_NEAR(rp.nearest.distance, gap, kTol) << "parallel, gap " << gap;
    ExpectConsistent(*a, IdentityRows(), *b, parallel, rp.nearest, 1e-9);
  }
}

TEST(AnalyticPairs, ParallelAndSkewSegments) {
  Patch segmentA;
  segmentA.kind = Patch::Kind::Mesh;
  segmentA.cell = CellType::Line;
  segmentA.points = {0, 0, 0, 1, 0, 0};
  segmentA.cells = {0, 1};
  const auto a = BuildModel(MeshGeometry(segmentA));
  // Parallel, overlapping in x: distance 1 along a whole stretch.
  const auto parallel = BuildModel(BezierCurve({{0.3, 1, 0}, {2, 1, 0}}));
  DistanceResult r = DistanceQuery(*a, IdentityRows(), *parallel, IdentityRows());
  EXPECT_NEAR(r.nearest.distance, 1.0, 1e-12);
  ExpectConsistent(*a, IdentityRows(), *parallel, IdentityRows(), r.nearest, 1e-12);
  EXPECT_GE(r.nearest.a.point[0], 0.3 - 1e-12);
  // Skew: the common perpendicular joins (0.5, 0, 0) and (0.5, 0, 1).
  const auto skew = BuildModel(BezierCurve({{0.5, -1, 1}, {0.5, 1, 1}}));
  r = DistanceQuery(*a, IdentityRows(), *skew, IdentityRows());
  EXPECT_NEAR(r.nearest.distance, 1.0, 1e-12);
  EXPECT_NEAR(r.nearest.a.point[0], 0.5, 1e-12);
  EXPECT_NEAR(r.nearest.b.point[1], 0.0, 1e-12);
  // The same segments as straight cubic Bezier curves (affine, not
  // simplices of degree 1: the joint solve, not the closed form).
  const auto cubicA = BuildModel(BezierCurve({{0, 0, 0}, {1.0 / 3, 0, 0}, {2.0 / 3, 0, 0}, {1, 0, 0}}));
  const auto cubicSkew = BuildModel(BezierCurve({{0.5, -1, 1}, {0.5, -1.0 / 3, 1}, {0.5, 1.0 / 3, 1}, {0.5, 1, 1}}));
  r = DistanceQuery(*cubicA, IdentityRows(), *cubicSkew, IdentityRows());
  EXPECT_NEAR(r.nearest.distance, 1.0, 1e-12);
  EXPECT_NEAR(r.nearest.a.params[0], 0.5, 1e-9);
  EXPECT_NEAR(r.nearest.b.params[0], 0.5, 1e-9);
  // Crossing segments (2D-like, in a plane): distance 0 at the crossing.
  const auto crossing = BuildModel(BezierCurve({{0.25, -1, 0}, {0.25, 1, 0}}));
  r = DistanceQuery(*a, IdentityRows(), *crossing, IdentityRows());
  EXPECT_EQ(r.nearest.distance, 0.0);
  EXPECT_NEAR(r.nearest.a.point[0], 0.25, 1e-12);
  // Beyond an end, leaning away: the two end points.
  const auto beyond = BuildModel(BezierCurve({{1.5, 0.5, 0.5}, {3, 1, 1}}));
  r = DistanceQuery(*a, IdentityRows(), *beyond, IdentityRows());
  const double end[3] = {1, 0, 0}, start[3] = {1.5, 0.5, 0.5};
  EXPECT_NEAR(r.nearest.distance, PointDistance(end, start), 1e-12);
}

TEST(AnalyticPairs, CurveTouchingASurface) {
  // A circle of radius 1 in the plane y = 0, centred at (0, 0, 1): it
  // touches the plane z = 0 at the origin and no more.
  Geometry circle = NurbsCircle(3, Frame{{0, 0, 1}, {1, 0, 0}, {0, 0, 1}}, 1.0);
  const auto curve = BuildModel(circle);
  const auto plane = BuildModel(PlaneSquare(2.0));
  DistanceResult r = DistanceQuery(*plane, IdentityRows(), *curve, IdentityRows());
  ASSERT_TRUE(r.nearest.found);
  EXPECT_EQ(r.nearest.distance, 0.0);
  EXPECT_NEAR(r.nearest.a.point[0], 0.0, 1e-5);  // tangential contact: the point is resolved to sqrt(tolerance)
  EXPECT_NEAR(r.nearest.a.point[2], 0.0, 1e-12);
  ExpectConsistent(*plane, IdentityRows(), *curve, IdentityRows(), r.nearest, 1e-9);
  // Lifted by 0.01: the distance is 0.01, at the touching point.
  const PoseRows lifted = RotationRows({0, 0, 1}, 0.0, {0, 0, 0.01});
  r = DistanceQuery(*plane, IdentityRows(), *curve, lifted);
  EXPECT_NEAR(r.nearest.distance, 0.01, kTol);
  EXPECT_NEAR(r.nearest.b.point[0], 0.0, 1e-7);
  // The same circle touching a sphere of radius 1 at the origin from outside.
  const auto sphere = BuildModel(NurbsSphere({0, 0, -1}, 1.0));
  r = DistanceQuery(*sphere, IdentityRows(), *curve, IdentityRows());
  EXPECT_EQ(r.nearest.distance, 0.0);
  ExpectConsistent(*sphere, IdentityRows(), *curve, IdentityRows(), r.nearest, 1e-9);
}

TEST(AnalyticPairs, MaxDistanceLeavesFarModelsNotFound) {
  const auto a = BuildModel(NurbsSphere({0, 0, 0}, 1.0));
  const auto b = BuildModel(NurbsSphere({0, 0, 0}, 0.5));
  const PoseRows poseB = RotationRows({0, 0, 1}, 0.0, {3, 0, 0});  // distance 1.5
  DistanceOptions options;
  options.maxDistance = 1.4;
  DistanceResult r = DistanceQuery(*a, IdentityRows(), *b, poseB, options);
  EXPECT_FALSE(r.nearest.found);
  options.maxDistance = 1.6;
  r = DistanceQuery(*a, IdentityRows(), *b, poseB, options);
  ASSERT_TRUE(r.nearest.found);
  EXPECT_NEAR(r.nearest.distance, 1.5, kTol);
}

TEST(AnalyticPairs, VolumesAnswerFromTheirBoundaryAndContainment) {
  const std::array<double, 3> lo{-1, -1, -1}, hi{1, 1, 1};
  const auto box = BuildModel(BoxHexMesh(lo, hi, 3));
  const auto sphere = BuildModel(NurbsSphere({0, 0, 0}, 0.25));
  // Outside: the box distance of the centre less the radius.
  for (const std::array<double, 3> c : {std::array<double, 3>{2.0, 0.3, -0.2}, {1.6, 1.7, 1.8}, {0.1, -1.9, 0.4}}) {
    const PoseRows poseB = RotationRows({1, 0, 0}, 0.5, c);
    const DistanceResult r = DistanceQuery(*box, IdentityRows(), *sphere, poseB);
    EXPECT_NEAR(r.nearest.distance, BoxDistance(lo, hi, c.data()) - 0.25, kTol);
    ExpectConsistent(*box, IdentityRows(), *sphere, poseB, r.nearest, 1e-9);
  }
  // Wholly inside the box: no boundary face is near, the distance is 0.
  const PoseRows inside = RotationRows({1, 0, 0}, 0.5, {0.2, 0.1, -0.3});
  DistanceResult r = DistanceQuery(*box, IdentityRows(), *sphere, inside);
  ASSERT_TRUE(r.nearest.found);
  EXPECT_EQ(r.nearest.distance, 0.0);
  EXPECT_NEAR(PointDistance(r.nearest.a.point, r.nearest.b.point), 0.0, 1e-9);
  EXPECT_EQ(CheckOnModel(sphere->geometry, inside, r.nearest.b, 1e-9), "");
  // Crossing the box's face: 0 as well.
  const PoseRows crossing = RotationRows({1, 0, 0}, 0.5, {1.1, 0.1, -0.3});
  r = DistanceQuery(*box, IdentityRows(), *sphere, crossing);
  EXPECT_EQ(r.nearest.distance, 0.0);
}

}  // namespace
}  // namespace invmap::testing
