// Every local minimum of the distance between two models (allMinima)
// against an independent dense-sampling reference: none missed, none
// extra, each once, nearest first; and analytic pairs with one minimum.
#include <gtest/gtest.h>

#include "tests/distance/distance_test_util.h"
#include "tests/support/distance_geometries.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

void CompareAllMinima(const Geometry& a, const Geometry& b, const PoseRows& poseB, double maxDistance,
                      int expectedAtLeast) {
  const auto ma = BuildModel(a);
  const auto mb = BuildModel(b);
  const double size = GeometrySize(a) + GeometrySize(b);
  DistanceOptions options;
  options.allMinima = true;
  options.maxDistance = maxDistance;
  const DistanceResult r = DistanceQuery(*ma, IdentityRows(), *mb, poseB, options);
  const std::vector<PairReferenceAnswer> reference =
      BruteForcePairMinima(a, IdentityRows(), b, poseB, maxDistance, 1e-5 * size);
  ASSERT_FALSE(r.minima.empty());
  EXPECT_TRUE(r.minima.front().certified);
  // The nearest of them is the distance.
  EXPECT_NEAR(r.minima.front().distance, r.nearest.distance, 1e-9 * size);
  for (std::size_t i = 0; i < r.minima.size(); ++i) {
    ExpectConsistent(*ma, IdentityRows(), *mb, poseB, r.minima[i], 1e-9 * size);
    if (i > 0) {
      EXPECT_LE(r.minima[i - 1].distance, r.minima[i].distance);
    }
    for (std::size_t j = 0; j < i; ++j) {
      EXPECT_FALSE(PointDistance(r.minima[i].a.point, r.minima[j].a.point) <= 1e-6 * size &&
                   PointDistance(r.minima[i].b.point, r.minima[j].b.point) <= 1e-6 * size)
          << "minima " << j << " and " << i << " are one";
    }
  }
  auto same = [&](const DistanceAnswer& f, const PairReferenceAnswer& ref) {
    return PointDistance(f.a.point, ref.a.point.data()) <= 1e-5 * size &&
           PointDistance(f.b.point, ref.b.point.data()) <= 1e-5 * size &&
           std::abs(f.distance - ref.distance) <= 1e-8 * size;
  };
  for (const PairReferenceAnswer& ref : reference) {
    bool matched = false;
    for (const DistanceAnswer& f : r.minima) matched = matched || same(f, ref);
    EXPECT_TRUE(matched) << "the reference's minimum " << ref.distance << " at " << ref.a.point[0] << " "
                         << ref.a.point[1] << " " << ref.a.point[2] << " is missing";
  }
  for (const DistanceAnswer& f : r.minima) {
    bool matched = false;
    for (const PairReferenceAnswer& ref : reference) matched = matched || same(f, ref);
    EXPECT_TRUE(matched) << "extra minimum " << f.distance << " at " << f.a.point[0] << " " << f.a.point[1] << " "
                         << f.a.point[2];
  }
  EXPECT_GE(static_cast<int>(r.minima.size()), expectedAtLeast);
}

TEST(PairMinima, WavyCurvesCrossing) {
  // A wavy curve over another one turned across it: minima where crests face.
  CompareAllMinima(WavyCurve(0.2, 3, 12), WavyCurve(0.15, 2, 9),
                   RotationRows({0, 0, 1}, 0.3, {0.1, 0.2, 0.5}), 1.0, 3);
}

TEST(PairMinima, CurveOverAnEggCrate) {
  CompareAllMinima(WavySurface(0.15, 2, 2, 4, false), WavyCurve(0.1, 2, 8),
                   RotationRows({1, 0, 0}, 3.14159265358979, {0.0, 0.55, 0.45}), 0.6, 2);
}

TEST(PairMinima, SpheresHaveOneMinimumAndMaxDistanceCuts) {
  const auto a = BuildModel(NurbsSphere({0, 0, 0}, 1.0));
  const auto b = BuildModel(NurbsSphere({0, 0, 0}, 0.5));
  const PoseRows poseB = RotationRows({1, 1, 0}, 0.5, {2.0, 0.5, -0.3});
  DistanceOptions options;
  options.allMinima = true;
  options.maxDistance = 1.0;
  const DistanceResult r = DistanceQuery(*a, IdentityRows(), *b, poseB, options);
  ASSERT_EQ(r.minima.size(), 1u);
  EXPECT_NEAR(r.minima[0].distance, std::sqrt(4.0 + 0.25 + 0.09) - 1.5, 1e-9);
  options.maxDistance = 0.5;
  EXPECT_TRUE(DistanceQuery(*a, IdentityRows(), *b, poseB, options).minima.empty());
}

}  // namespace
}  // namespace invmap::testing
