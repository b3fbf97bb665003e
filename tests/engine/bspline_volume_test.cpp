// Whole-engine inversion on B-spline volumes (a bent, twisted block with a
// repeated knot and a small rational block): points inside must come back
// with distance 0 and parameters that map onto them; points outside get the
// closest boundary point. Checked against the brute-force reference.
#include <gtest/gtest.h>

#include "invmap/invmap.h"
#include "tests/support/closest_reference.h"
#include "tests/support/family_runner.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

void RunVolumes(const char* name, const QueryMix& mix, std::uint64_t seed) {
  const Geometry g = BSplineVolumes();
  ReferenceGeometry reference(g);
  const QuerySet q = MakeQueries(reference.cells(), 3, reference.size(), mix, seed);
  RunFamily(name, g, q, [&](const double* p) { return reference.Closest(p); });
}

TEST(BSplineVolumeTest, InsidePoints) {
  QueryMix mix;
  mix.inside = 45000;
  mix.on = 5000;  // points of random cells: inside or on a face
  RunVolumes("volumes inside", mix, 701);
}

TEST(BSplineVolumeTest, OutsidePoints) {
  QueryMix mix;
  mix.near = 25000;
  mix.mid = 10000;
  mix.far = 15000;
  RunVolumes("volumes outside", mix, 702);
}

}  // namespace
}  // namespace invmap::testing
