// Model-to-model distances against an independent brute force (dense
// sampling of both models, polished by a joint local solve of the tests'
// own): curves and surfaces of B-splines and NURBS whose distance has
// several local minima, under random poses; triangle meshes against all
// pairs of triangles.
#include <gtest/gtest.h>

#include <random>

#include "tests/distance/distance_test_util.h"
#include "tests/support/distance_geometries.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

struct Case {
  const char* name;
  Geometry a, b;
};

/// Random poses that keep B near A (within `reach` of the origin) and turned.
PoseRows RandomPose(std::mt19937_64& rng, double reach) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return RotationRows({u(rng), u(rng), u(rng)}, 3.0 * u(rng), {reach * u(rng), reach * u(rng), reach * u(rng)});
}

void CompareWithBruteForce(const Case& c, int poses, std::uint64_t seed, double reach) {
  const auto a = BuildModel(c.a);
  const auto b = BuildModel(c.b);
  const double size = GeometrySize(c.a) + GeometrySize(c.b);
  std::mt19937_64 rng(seed);
  for (int trial = 0; trial < poses; ++trial) {
    const PoseRows poseA = trial % 2 ? RandomPose(rng, 0.0) : IdentityRows();
    const PoseRows poseB = RandomPose(rng, reach);
    const DistanceResult r = DistanceQuery(*a, poseA, *b, poseB);
    const PairReferenceAnswer ref = BruteForcePairDistance(c.a, poseA, c.b, poseB);
    SCOPED_TRACE(std::string(c.name) + ", pose " + std::to_string(trial));
    ExpectConsistent(*a, poseA, *b, poseB, r.nearest, 1e-9 * size);
    // Never farther than the reference, which is an upper bound of the
    // true minimum (its answer is realized by points of the models, and so
    // is invmap's: it cannot be nearer than the true minimum).
    EXPECT_LE(r.nearest.distance, ref.distance + 1e-9 * size);
    // And the reference finds the same minimum (it resolves these basins).
    EXPECT_NEAR(r.nearest.distance, ref.distance, 1e-7 * size);
    EXPECT_TRUE(r.nearest.certified);
  }
}

TEST(BruteForcePairs, CurveAndCurve) {
  CompareWithBruteForce({"wavy curves", WavyCurve(0.2, 3, 12), WavyCurve(0.15, 2, 9)}, 6, 11, 0.4);
}

TEST(BruteForcePairs, CurveAndSurface) {
  CompareWithBruteForce({"curve over surface", WavyCurve(0.2, 3, 12), WavySurface(0.1, 2, 1, 6, false)}, 6, 12, 0.4);
}

TEST(BruteForcePairs, SurfaceAndSurface) {
  CompareWithBruteForce({"polynomial and rational surfaces", WavySurface(0.1, 2, 1, 5, false),
                         WavySurface(0.08, 1, 2, 4, true)},
                        5, 13, 0.5);
}

TEST(BruteForcePairs, TriangleMeshes) {
  const Patch sphere = BumpySphereMesh(14, 9, {0, 0, 0}, 1.0);
  const Patch small = BumpySphereMesh(9, 6, {0, 0, 0}, 0.4);
  const auto a = BuildModel(MeshGeometry(sphere));
  const auto b = BuildModel(MeshGeometry(small));
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 12; ++trial) {
    // From overlapping to apart.
    const double distance = 0.8 + 1.2 * trial / 11.0;
    std::array<double, 3> t{u(rng), u(rng), u(rng)};
    const double norm = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    for (double& x : t) x *= distance / norm;
    const PoseRows poseB = RotationRows({u(rng), u(rng), u(rng)}, 3.0 * u(rng), t);
    const DistanceResult r = DistanceQuery(*a, IdentityRows(), *b, poseB);
    const double expected = AllPairsMeshDistance(sphere, IdentityRows(), small, poseB);
    SCOPED_TRACE("pose " + std::to_string(trial));
    EXPECT_NEAR(r.nearest.distance, expected, 1e-12);
    ExpectConsistent(*a, IdentityRows(), *b, poseB, r.nearest, 1e-12);
  }
}

}  // namespace
}  // namespace invmap::testing
