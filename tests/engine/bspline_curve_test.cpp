// Whole-engine inversion on B-spline curves in 2D and 3D (many spans,
// repeated and C0 knots, unclamped ends, rational weights, degree 1 to 5)
// against the brute-force reference. Curve ends are the classic trap: points
// beyond an end must get the end point, not a perpendicular foot.
#include <gtest/gtest.h>

#include "invmap/invmap.h"
#include "tests/support/closest_reference.h"
#include "tests/support/family_runner.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

void RunCurves(int dim, std::uint64_t seed) {
  const Geometry g = BSplineCurves(dim);
  ReferenceGeometry reference(g);
  QueryMix mix;
  mix.on = 4000;
  mix.near = 28000;
  mix.mid = 14000;
  mix.far = 14000;
  const QuerySet q = MakeQueries(reference.cells(), dim, reference.size(), mix, seed);
  RunFamily(dim == 2 ? "curves 2D" : "curves 3D", g, q, [&](const double* p) { return reference.Closest(p); });
}

TEST(BSplineCurveTest, Curves2D) { RunCurves(2, 601); }

TEST(BSplineCurveTest, Curves3D) { RunCurves(3, 602); }

}  // namespace
}  // namespace invmap::testing
