// The pair certificate on simple isolated minima in the frames users meet
// most: models aligned with the axes, nearly touching, and models far apart
// relative to their size. Each answer is checked against an analytic
// distance or the dense reference, and must come back certified.
#include <gtest/gtest.h>

#include <string>

#include "samples/sample_geometries.h"
#include "tests/distance/distance_test_util.h"
#include "tests/support/distance_geometries.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

/// The segment from (0, 0, 0) to (1, 0, 0), as a linear B-spline curve.
Geometry Segment() {
  Patch patch;
  patch.kind = Patch::Kind::BSpline;
  patch.degrees = {1};
  patch.counts = {2};
  patch.knots = {{0, 0, 1, 1}};
  patch.points = {0, 0, 0, 1, 0, 0};
  Geometry g;
  g.patches.push_back(std::move(patch));
  return g;
}

/// The parabola z = 4 (x - 1/2)^2 over x in [0, 1] in the plane y = 0 (a
/// quadratic Bezier curve, its vertex at the middle of its parameter).
Geometry Parabola() { return BezierCurve({{{0, 0, 1}}, {{0.5, 0, -1}}, {{1, 0, 1}}}); }

TEST(PairCertificateFrames, SegmentUnderAParabolaInTheAxisFrame) {
  // The parabola lifted by h and moved along the segment: its vertex faces
  // the segment's point (0.6, 0, 0) at distance h, the only minimum. The
  // certificate once failed here for every h (the Hessian's change was
  // measured across the vertex, where it is symmetric; the nets' rounding
  // ate the tolerance of small distances).
  const auto segment = BuildModel(Segment());
  const auto parabola = BuildModel(Parabola());
  for (const double h : {0.3, 0.1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6}) {
    SCOPED_TRACE("h = " + std::to_string(h));
    const PoseRows pose = RotationRows({0, 0, 1}, 0.0, {0.1, 0.0, h});
    const DistanceResult r = DistanceQuery(*segment, IdentityRows(), *parabola, pose);
    ASSERT_TRUE(r.nearest.found);
    EXPECT_NEAR(r.nearest.distance, h, 1e-12);
    EXPECT_NEAR(r.nearest.a.point[0], 0.6, 1e-6);
    EXPECT_TRUE(r.nearest.certified);
  }
}

TEST(PairCertificateFrames, ModelsFarApart) {
  // A wavy cubic curve and a wavy bicubic surface, each about 1 across,
  // 1e2 to 1e6 apart: the nets of |x - y|^2 once carried the squared
  // separation's rounding, above the distance tolerance beyond a few
  // hundred sizes.
  const Geometry curve = WavyCurve(0.2, 2, 6);
  const Geometry surface = WavySurface(0.1, 1, 1, 3, false);
  const auto a = BuildModel(curve);
  const auto b = BuildModel(surface);
  for (const double separation : {1e2, 1e4, 1e6}) {
    SCOPED_TRACE("separation " + std::to_string(separation));
    const PoseRows pose = RotationRows({1, 2, 0.5}, 0.7, {separation, 0.3 * separation, -0.2 * separation});
    const DistanceResult r = DistanceQuery(*a, IdentityRows(), *b, pose);
    ASSERT_TRUE(r.nearest.found);
    EXPECT_TRUE(r.nearest.certified);
    const PairReferenceAnswer reference = BruteForcePairDistance(curve, IdentityRows(), surface, pose);
    // Never farther than the polished reference, and no nearer than
    // rounding of coordinates of that magnitude allows.
    EXPECT_LE(r.nearest.distance, reference.distance + 1e-9 * separation);
    EXPECT_GE(r.nearest.distance, reference.distance - 1e-12 * separation);
    ExpectConsistent(*a, IdentityRows(), *b, pose, r.nearest, 1e-14 * separation);
  }
}

TEST(PairCertificateFrames, SurfaceInATorusHoleTurnedSlightly) {
  // The wavy surface over [0, 1]^2 in the hole of a torus (major radius 2,
  // tube 0.7) around the vertical through (0.5, 0.5), the torus turned by
  // 1e-3 rad or less: one corner of the surface is nearest, held there by
  // both of its edges' multipliers while the distance bends down along
  // them. The certificate once scaled those directions by the floor of the
  // Hessian's diagonal and lost them.
  const auto surface = BuildModel(samples::WavySurface(8));
  const auto torus = BuildModel(samples::NurbsTorus(2.0, 0.7));
  for (const double angle : {0.0, 2e-4, 1e-3}) {
    for (const double z : {0.6, 0.65}) {
      SCOPED_TRACE("angle " + std::to_string(angle) + ", z " + std::to_string(z));
      const PoseRows pose = RotationRows({0.2, 0.1, 1.0}, angle, {0.5, 0.5, z});
      const DistanceResult r = DistanceQuery(*surface, IdentityRows(), *torus, pose);
      ASSERT_TRUE(r.nearest.found);
      EXPECT_TRUE(r.nearest.certified);
      // The corners, in the torus's frame (R^T (x - t)), in closed form.
      double nearestCorner = 1e300;
      for (const double cx : {0.0, 1.0}) {
        for (const double cy : {0.0, 1.0}) {
          const double corner[3] = {cx - pose[3], cy - pose[7], 0.125 - pose[11]};
          double local[3];
          for (int k = 0; k < 3; ++k) local[k] = pose[k] * corner[0] + pose[4 + k] * corner[1] + pose[8 + k] * corner[2];
          nearestCorner = std::min(nearestCorner, TorusDistance({0, 0, 0}, 2.0, 0.7, local));
        }
      }
      EXPECT_NEAR(r.nearest.distance, nearestCorner, 1e-12);
      ExpectConsistent(*surface, IdentityRows(), *torus, pose, r.nearest, 1e-9);
    }
  }
}

TEST(PairCertificateFrames, CurveInsideAVolumeListsTheOverlap) {
  // A curve wholly inside a hexahedral box: distance 0 with a common
  // point; the points at distance 0 are a continuum, so the list of minima
  // holds that common point and is not certified complete.
  const auto box = BuildModel(BoxHexMesh({0, 0, 0}, {1, 1, 1}, 2));
  const auto curve = BuildModel(BezierCurve({{{0.2, 0.4, 0.5}}, {{0.5, 0.7, 0.4}}, {{0.8, 0.5, 0.6}}}));
  const PoseRows pose = IdentityRows();
  DistanceOptions options;
  options.allMinima = true;
  const DistanceResult r = DistanceQuery(*box, IdentityRows(), *curve, pose, options);
  ASSERT_TRUE(r.nearest.found);
  EXPECT_EQ(r.nearest.distance, 0.0);
  ASSERT_EQ(r.minima.size(), 1u);
  EXPECT_EQ(r.minima[0].distance, 0.0);
  EXPECT_LE(PointDistance(r.minima[0].a.point, r.nearest.a.point), 0.0);
  EXPECT_FALSE(r.minima[0].certified);
}

}  // namespace
}  // namespace invmap::testing
