// Whole-engine inversion on curved quadratic Bezier meshes: hexes written as
// one Bezier patch per element, tets as one BezierCells patch. Interior
// points must be found inside an element (distance 0), shared faces must not
// confuse the search, outside points get the closest boundary point.
// Checked against the brute-force reference.
#include <gtest/gtest.h>

#include "invmap/invmap.h"
#include "tests/support/closest_reference.h"
#include "tests/support/family_runner.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

void RunMesh(bool hexes, const char* name, const QueryMix& mix, std::uint64_t seed) {
  const Geometry g = QuadraticMesh(hexes);
  ReferenceGeometry reference(g);
  const QuerySet q = MakeQueries(reference.cells(), 3, reference.size(), mix, seed);
  RunFamily(name, g, q, [&](const double* p) { return reference.Closest(p); });
}

QueryMix InsideMix() {
  QueryMix mix;
  mix.inside = 40000;
  mix.on = 5000;
  mix.near = 5000;
  return mix;
}

QueryMix OutsideMix() {
  QueryMix mix;
  mix.near = 25000;
  mix.mid = 10000;
  mix.far = 15000;
  return mix;
}

TEST(QuadraticMeshTest, HexInside) { RunMesh(true, "quadratic hexes inside", InsideMix(), 801); }
TEST(QuadraticMeshTest, HexOutside) { RunMesh(true, "quadratic hexes outside", OutsideMix(), 802); }
TEST(QuadraticMeshTest, TetInside) { RunMesh(false, "quadratic tets inside", InsideMix(), 803); }
TEST(QuadraticMeshTest, TetOutside) { RunMesh(false, "quadratic tets outside", OutsideMix(), 804); }

}  // namespace
}  // namespace invmap::testing
