// Points inside a cell as wide as the space it lies in (a volume in 3D, a
// surface in the plane) are their own closest points: distance exactly 0
// and the query itself as the closest point, whichever path answers them
// (linear simplices in closed form, curved cells by Newton, Morton-ordered
// batches with warm starts). QA found 2D triangles and quads reported an
// ulp to 1e-14 of their size away, with the map at the solved parameters
// as the closest point, where 3D tets gave 0. The parameters must still be
// the point's preimage.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "invmap/invmap.h"
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
  const std::int64_t cells = m.NumCells(0);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.02, 0.98);
  const int n = 4000;
  std::vector<double> xyz;
  for (int q = 0; q < n; ++q) {
    const double sample[3] = {unit(rng), unit(rng), unit(rng)};
    double params[3], point[3];
    ASSERT_TRUE(m.PointAt(0, static_cast<std::int64_t>(q * 7919) % cells, sample, params, point));
    xyz.insert(xyz.end(), point, point + dim);
  }
  Results r;
  ASSERT_EQ(m.Invert(PointsView::Interleaved(xyz.data(), n, dim), InversionOptions{}, &r), Error::Ok);
  int wrong = 0, offPreimage = 0;
  const bool tensor = type == CellType::Quad || type == CellType::Hex;
  for (int q = 0; q < n; ++q) {
    const double* x = &xyz[static_cast<size_t>(q) * dim];
    bool exact = r.status[q] == Status::Found && r.distance[q] == 0.0;
    for (int k = 0; k < dim; ++k) exact = exact && r.closest[3 * q + k] == x[k];
    wrong += !exact;
    if (!tensor || r.status[q] != Status::Found) continue;
    // Tensor cells map [0, 1]^d uniformly: the reported parameters are a sample.
    const double sample[3] = {r.params[3 * q], r.params[3 * q + 1], dim == 3 ? r.params[3 * q + 2] : 0.5};
    double params[3], back[3];
    ASSERT_TRUE(m.PointAt(r.patch[q], r.cell[q], sample, params, back));
    double d2 = 0.0;
    for (int k = 0; k < dim; ++k) d2 += (back[k] - x[k]) * (back[k] - x[k]);
    offPreimage += !(std::sqrt(d2) <= 1e-12);
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
