// Whole-engine inversion on geometries mixing every patch kind and cell
// type (B-spline surfaces and curves, Bezier cells of all six types, linear
// meshes of all six types, a BezierCells patch), in 3D and 2D, against the
// brute-force reference. Reported (patch, cell, params) must map onto the
// closest point whatever the kind.
#include <gtest/gtest.h>

#include "invmap/invmap.h"
#include "tests/support/closest_reference.h"
#include "tests/support/family_runner.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

void RunMixed(const char* name, const Geometry& g, const QueryMix& mix, std::uint64_t seed) {
  ReferenceGeometry reference(g);
  const QuerySet q = MakeQueries(reference.cells(), g.dimension, reference.size(), mix, seed);
  RunFamily(name, g, q, [&](const double* p) { return reference.Closest(p); });
}

TEST(MultiPatchTest, Mixed3DNear) {
  QueryMix mix;
  mix.on = 5000;
  mix.near = 35000;
  mix.inside = 10000;
  RunMixed("mixed 3D near", MixedGeometry3(), mix, 1001);
}

TEST(MultiPatchTest, Mixed3DFar) {
  QueryMix mix;
  mix.mid = 25000;
  mix.far = 25000;
  RunMixed("mixed 3D mid/far", MixedGeometry3(), mix, 1002);
}

TEST(MultiPatchTest, Mixed2D) {
  QueryMix mix;
  mix.on = 5000;
  mix.near = 45000;
  mix.mid = 20000;
  mix.far = 20000;
  mix.inside = 10000;
  RunMixed("mixed 2D", MixedGeometry2(), mix, 1003);
}

}  // namespace
}  // namespace invmap::testing
