// Every local minimum of the distance between two models (allMinima)
// against an independent dense-sampling reference
// (tests/distance/all_minima_check.h): none missed, none extra, each once,
// nearest first; and analytic pairs with one minimum.
#include <gtest/gtest.h>

#include "tests/distance/all_minima_check.h"
#include "tests/distance/distance_test_util.h"
#include "tests/support/distance_geometries.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

void CompareAllMinima(const Geometry& a, const Geometry& b, const PoseRows& poseB, double maxDistance,
                      int expectedAtLeast) {
  std::size_t listed = 0;
  CheckAllMinima(a, b, poseB, maxDistance, "", true, &listed);
  EXPECT_GE(static_cast<int>(listed), expectedAtLeast);
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
