// A boundary layer of a CFD mesh: linear hexes over a curved sheet, a
// hundred thousand to ten million times thinner than they are long, queried
// in batches (Morton order, warm starts from the neighbours' answers). Every
// query is a point of the mesh, built here by trilinear interpolation of a
// hex's vertices, so the answer is known: distance zero, and the reported
// parameters give the point back. QA found inside points of such cells put
// on a face, 1e-8 of the size away.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "invmap/invmap.h"
#include "tests/support/patch_reference.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

constexpr int kCells = 12;  // along each of the sheet's two directions; two layers through the thickness

/// The layer's vertices: a bent sheet over [0, 1]^2, `thickness` thick.
Vec3 Layer(double a, double b, double c, double thickness) {
  return Vec3{a + 0.2 * b * b, b + 0.1 * std::sin(2 * a),
              0.3 * (a - 0.5) * (a - 0.5) + 0.2 * a * b + thickness * c * (1 + 0.3 * a)};
}

/// The point at (a, b, c) in [0, 1]^3 of hex (i, j, k) of the grid: trilinear
/// interpolation of its eight vertices.
std::array<double, 3> PointOfHex(int i, int j, int k, double a, double b, double c, double thickness) {
  std::array<double, 3> x{0, 0, 0};
  for (int corner = 0; corner < 8; ++corner) {
    const int di = corner & 1, dj = (corner >> 1) & 1, dk = corner >> 2;
    const double weight = (di ? a : 1 - a) * (dj ? b : 1 - b) * (dk ? c : 1 - c);
    const Vec3 v = Layer(static_cast<double>(i + di) / kCells, static_cast<double>(j + dj) / kCells,
                         static_cast<double>(k + dk) / 2, thickness);
    for (int d = 0; d < 3; ++d) x[d] += weight * v[d];
  }
  return x;
}

TEST(ThinLayerTest, PointsOfAThinHexLayerAreFoundOnItInBatches) {
  for (const double thickness : {1e-5, 1e-6, 1e-7}) {
    Geometry g;
    g.patches.push_back(GridMesh(CellType::Hex, 3, kCells, kCells, 2,
                                 [&](double a, double b, double c) { return Layer(a, b, c, thickness); }));
    BuildResult built = Manifold::Build(g);
    ASSERT_TRUE(built.error.empty()) << built.error;
    const Manifold& m = built.manifold;
    std::mt19937_64 rng(77);
    std::uniform_int_distribution<int> cellIndex(0, kCells - 1), layer(0, 1);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<double> xyz;
    const int n = 20000;
    for (int q = 0; q < n; ++q) {
      // A third of the points within 1e-3 of a layer's bottom face.
      const double c = q % 3 == 0 ? 1e-3 * unit(rng) : unit(rng);
      const std::array<double, 3> x =
          PointOfHex(cellIndex(rng), cellIndex(rng), layer(rng), unit(rng), unit(rng), c, thickness);
      xyz.insert(xyz.end(), x.begin(), x.end());
    }
    Results r;
    ASSERT_EQ(m.Invert(PointsView::Interleaved(xyz.data(), n, 3), {}, &r), Error::Ok);
    // Cells are about 0.12 long: the solver's tolerance (1e-11 of a cell's size) is below this.
    const double tolerance = 2e-12;
    int failures = 0;
    for (int q = 0; q < n; ++q) {
      const double* query = &xyz[3 * q];
      // Mapped back by the tests' own evaluation of the mesh, not the engine's.
      double point[3] = {0, 0, 0};
      const bool mapped =
          r.status[q] == Status::Found && EvaluateReported(g, r.patch[q], r.cell[q], &r.params[3 * q], 1e-12, point).empty();
      const double back = std::hypot(point[0] - query[0], point[1] - query[1], point[2] - query[2]);
      if (mapped && r.distance[q] <= tolerance && back <= tolerance) continue;
      if (failures++ < 5) {
        ADD_FAILURE() << "thickness " << thickness << ", point " << q << " (" << query[0] << ", " << query[1] << ", "
                      << query[2] << "): distance " << r.distance[q] << " in cell " << r.cell[q] << " at ("
                      << r.params[3 * q] << ", " << r.params[3 * q + 1] << ", " << r.params[3 * q + 2]
                      << "), whose point is " << back << " from the query";
      }
    }
    EXPECT_EQ(failures, 0) << "thickness " << thickness << ", of " << n;
  }
}

}  // namespace
}  // namespace invmap::testing
