// Points inside a cell as wide as the space it lies in (a volume in 3D, a
// surface in the plane) are their own closest points: distance exactly 0
// and the query itself as the closest point, whichever path answers them
// (linear simplices in closed form, curved cells by Newton, Morton-ordered
// batches with warm starts). QA found 2D triangles and quads reported an
// ulp to 1e-14 of their size away, with the map at the solved parameters
// as the closest point, where 3D tets gave 0. The parameters must still be
// the point's preimage.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "invmap/invmap.h"
#include "tests/support/patch_reference.h"
#include "tests/support/reference_cell.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

/// A warped unit square or cube: bilinear and trilinear cells are curved.
Vec3 Warp(double a, double b, double c) {
  return Vec3{a + 0.15 * b * b + 0.05 * c, b + 0.1 * std::sin(2 * a) + 0.05 * c * a, c + 0.1 * a * b};
}

void ExpectInsidePointsExact(const std::string& name, CellType type, int dim, int nz) {
  Geometry g;
  g.dimension = dim;
  g.patches.push_back(GridMesh(type, dim, 6, 5, nz, Warp));
  BuildResult built = Manifold::Build(g);
  ASSERT_TRUE(built.error.empty()) << name << ": " << built.error;
  const Manifold& m = built.manifold;
  // The points are made, and the answers' parameters mapped back, by the
  // tests' own evaluation of the mesh (tests/support/patch_reference.h),
  // not by the engine's Manifold::PointAt.
  const std::vector<PatchCell> cells = PatchCells(g, 0);
  std::mt19937_64 rng(5);
  const int n = 4000;
  std::vector<double> xyz;
  for (int q = 0; q < n; ++q) {
    const RefCell& cell = cells[static_cast<std::size_t>(q) * 7919 % cells.size()].cell;
    // Away from the faces by 2% of the domain, as before: inside, not on.
    std::array<double, 3> ref = RandomRefPoint(cell.type, rng);
    const std::array<double, 3> center = RefDomainCenter(cell.type);
    for (int k = 0; k < 3; ++k) ref[k] = center[k] + 0.96 * (ref[k] - center[k]);
    double point[3] = {0, 0, 0};
    RefEvaluate(cell, ref.data(), point);
    xyz.insert(xyz.end(), point, point + dim);
  }
  Results r;
  ASSERT_EQ(m.Invert(PointsView::Interleaved(xyz.data(), n, dim), InversionOptions{}, &r), Error::Ok);
  int wrong = 0, offPreimage = 0;
  for (int q = 0; q < n; ++q) {
    const double* x = &xyz[static_cast<size_t>(q) * dim];
    bool exact = r.status[q] == Status::Found && r.distance[q] == 0.0;
    for (int k = 0; k < dim; ++k) exact = exact && r.closest[3 * q + k] == x[k];
    wrong += !exact;
    if (r.status[q] != Status::Found) continue;
    // The reported parameters are the point's preimage.
    double back[3] = {0, 0, 0};
    const std::string why = EvaluateReported(g, r.patch[q], r.cell[q], &r.params[3 * q], 1e-12, back);
    double d2 = 0.0;
    for (int k = 0; k < dim; ++k) d2 += (back[k] - x[k]) * (back[k] - x[k]);
    offPreimage += !why.empty() || !(std::sqrt(d2) <= 1e-12);
  }
  EXPECT_EQ(wrong, 0) << name << ": of " << n << " inside points, not at distance 0 with themselves as closest";
  EXPECT_EQ(offPreimage, 0) << name << ": parameters that do not map back to the point";
}

TEST(InsideExactTest, PlanarTrianglesAndQuads) {
  ExpectInsidePointsExact("tri 2d", CellType::Tri, 2, 0);
  ExpectInsidePointsExact("quad 2d", CellType::Quad, 2, 0);
}

TEST(InsideExactTest, Volumes) {
  ExpectInsidePointsExact("tet", CellType::Tet, 3, 4);
  ExpectInsidePointsExact("hex", CellType::Hex, 3, 4);
  ExpectInsidePointsExact("wedge", CellType::Wedge, 3, 4);
}

}  // namespace
}  // namespace invmap::testing
