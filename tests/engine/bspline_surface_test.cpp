// Whole-engine inversion on B-spline surfaces with hundreds of spans and
// repeated interior knots (polynomial and rational, clamped and unclamped),
// against the brute-force reference of tests/support/closest_reference.h.
#include <gtest/gtest.h>

#include "invmap/invmap.h"
#include "tests/support/closest_reference.h"
#include "tests/support/family_runner.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

/// Compares `mix` queries (seeded) on the two wavy surfaces.
void RunWavySurfaces(const char* name, const QueryMix& mix, std::uint64_t seed) {
  const Geometry g = WavySurfaces();
  ReferenceGeometry reference(g);
  const QuerySet q = MakeQueries(reference.cells(), 3, reference.size(), mix, seed);
  RunFamily(name, g, q, [&](const double* p) { return reference.Closest(p); });
}

TEST(BSplineSurfaceTest, NearPoints) {
  QueryMix mix;
  mix.on = 5000;
  mix.near = 45000;
  RunWavySurfaces("wavy surfaces near", mix, 501);
}

TEST(BSplineSurfaceTest, MidAndFarPoints) {
  QueryMix mix;
  mix.mid = 20000;
  mix.far = 30000;
  RunWavySurfaces("wavy surfaces mid/far", mix, 502);
}

}  // namespace
}  // namespace invmap::testing
