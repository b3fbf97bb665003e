// The curved cells' lanes in the batch (engine/bucket_lanes.h on curves and
// surfaces, engine/volume_lanes.h inside curved tetrahedra): every answer is
// checked against the brute-force reference for several bucket sizes (the
// lanes solve a bucket's points together, so the bucket decides which
// points share a lane) and gap tolerances (the lanes' bounds), with the
// pointwise mode (which never uses them) beside; and the answers are the
// same bits for any thread count.
#include <gtest/gtest.h>

#include <string>

#include "invmap/invmap.h"
#include "tests/support/closest_reference.h"
#include "tests/support/family_runner.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

/// `mix` queries around `g` against the reference, for bucket sizes that
/// put from a few to hundreds of points in a lane, with and without a gap
/// tolerance, and pointwise.
void RunLanes(const char* name, const Geometry& g, const QueryMix& mix, std::uint64_t seed) {
  ReferenceGeometry reference(g);
  const QuerySet q = MakeQueries(reference.cells(), g.dimension, reference.size(), mix, seed);
  for (int bucketSize : {5, 32, 256}) {
    InversionOptions options;
    options.bucketSize = bucketSize;
    RunFamily((std::string(name) + ", bucket " + std::to_string(bucketSize)).c_str(), g, q,
              [&](const double* p) { return reference.Closest(p); }, options);
  }
  // A gap tolerance inside the spread of the points: many lanes end Farther.
  InversionOptions gap;
  gap.maxDistance = 0.02 * reference.size();
  RunFamily((std::string(name) + ", gap tolerance").c_str(), g, q,
            [&](const double* p) { return reference.Closest(p); }, gap);
  InversionOptions pointwise;
  pointwise.pointwise = true;
  RunFamily((std::string(name) + ", pointwise").c_str(), g, q, [&](const double* p) { return reference.Closest(p); },
            pointwise);
}

/// The same bits for 1, 2 and 7 threads (bucket sizes 7 and 32).
void ExpectThreadInvariant(const Geometry& g, const QueryMix& mix, std::uint64_t seed) {
  ReferenceGeometry reference(g);
  const QuerySet q = MakeQueries(reference.cells(), g.dimension, reference.size(), mix, seed);
  const BuildResult built = Manifold::Build(g);
  ASSERT_TRUE(built.error.empty()) << built.error;
  ExpectSameBitsOnThreads("curved lanes", built.manifold, q, {7, 32});
}

QueryMix NearMix() {
  QueryMix mix;
  mix.on = 1000;
  mix.near = 6000;
  mix.mid = 1500;
  mix.far = 500;
  return mix;
}

TEST(CurvedLanesTest, Surfaces) { RunLanes("wavy surfaces", WavySurfaces(), NearMix(), 2801); }

TEST(CurvedLanesTest, Curves) {
  RunLanes("3D curves", BSplineCurves(3), NearMix(), 2802);
  RunLanes("2D curves", BSplineCurves(2), NearMix(), 2803);
}

TEST(CurvedLanesTest, QuadraticTets) {
  QueryMix mix;
  mix.inside = 8000;
  mix.on = 500;
  mix.near = 1000;
  mix.mid = 500;
  RunLanes("quadratic tets", QuadraticMesh(false), mix, 2804);
}

TEST(CurvedLanesTest, ThreadCountDoesNotChangeAnyBit) {
  ExpectThreadInvariant(WavySurfaces(), NearMix(), 2805);
  ExpectThreadInvariant(BSplineCurves(3), NearMix(), 2806);
  QueryMix inside;
  inside.inside = 6000;
  inside.near = 1000;
  ExpectThreadInvariant(QuadraticMesh(false), inside, 2807);
}

}  // namespace
}  // namespace invmap::testing
