// Affine regions (algorithm 6): B-spline patches whose cells share one affine
// map are searched as blocks. Checked against analytic answers (a flat plate
// is a parallelogram, an affine block volume a parallelepiped) and, for a
// plate with a curved band, against the brute-force reference; and the
// regions found must be exactly the blocks of cells with one map.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "engine/cell_store.h"
#include "invmap/invmap.h"
#include "tests/engine/built_cells.h"
#include "tests/support/closest_reference.h"
#include "tests/support/family_runner.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

/// Greville abscissa of control point i in knot units (mean of knots i+1 .. i+p).
double GrevilleAbscissa(const std::vector<double>& knots, int p, int i) {
  double sum = 0;
  for (int k = 1; k <= p; ++k) sum += knots[i + k];
  return sum / p;
}

/// A B-spline patch with control points A * (Greville abscissae) + b: by
/// linear precision the patch is exactly the affine map u -> A u + b.
/// `bump(i, j, k)` (optional) lifts control point (i, j, k) along `lift`.
Patch AffineBSpline(const std::vector<int>& degrees, const std::vector<std::vector<double>>& knots,
                    const Eigen::Matrix3d& A, const Eigen::Vector3d& b, double (*bump)(int, int, int) = nullptr,
                    const Eigen::Vector3d& lift = Eigen::Vector3d::Zero()) {
  Patch patch;
  patch.kind = Patch::Kind::BSpline;
  patch.degrees = degrees;
  patch.knots = knots;
  const int pd = static_cast<int>(degrees.size());
  for (int d = 0; d < pd; ++d) patch.counts.push_back(static_cast<int>(knots[d].size()) - degrees[d] - 1);
  const int n[3] = {patch.counts[0], pd > 1 ? patch.counts[1] : 1, pd > 2 ? patch.counts[2] : 1};
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        Eigen::Vector3d u = Eigen::Vector3d::Zero();
        const int index[3] = {i, j, k};
        for (int d = 0; d < pd; ++d) u[d] = GrevilleAbscissa(knots[d], degrees[d], index[d]);
        Eigen::Vector3d x = A * u + b;
        if (bump) x += bump(i, j, k) * lift;
        patch.points.insert(patch.points.end(), {x[0], x[1], x[2]});
      }
  return patch;
}

/// Closest point of the parallelogram o + s e1 + t e2, s, t in [0, 1].
double ParallelogramDistance(const Eigen::Vector3d& o, const Eigen::Vector3d& e1, const Eigen::Vector3d& e2,
                             const Eigen::Vector3d& p, Eigen::Vector3d* closest) {
  Eigen::Matrix<double, 3, 2> E;
  E << e1, e2;
  const Eigen::Vector2d st = (E.transpose() * E).ldlt().solve(E.transpose() * (p - o));
  if (st.minCoeff() >= 0 && st.maxCoeff() <= 1) {
    *closest = o + E * st;
    return (p - *closest).norm();
  }
  const Eigen::Vector3d corners[4] = {o, o + e1, o + e1 + e2, o + e2};
  double best = 1e300;
  for (int c = 0; c < 4; ++c) {
    double s, x[3];
    ClosestOnSegment(p.data(), corners[c].data(), corners[(c + 1) % 4].data(), &s, x);
    const Eigen::Vector3d candidate(x[0], x[1], x[2]);
    if ((p - candidate).norm() < best) {
      best = (p - candidate).norm();
      *closest = candidate;
    }
  }
  return best;
}

Eigen::Matrix3d PlateMap() {
  Eigen::Matrix3d A;
  A << 2.0, 0.3, 0, -0.4, 1.5, 0, 0.7, 0.2, 0;
  return A;
}

Geometry Plate(double (*bump)(int, int, int) = nullptr) {
  std::mt19937_64 rng(41);
  Geometry g;
  g.patches.push_back(AffineBSpline({3, 2}, {RandomKnots(3, 30, 5, true, rng), RandomKnots(2, 20, 4, true, rng)},
                                    PlateMap(), Eigen::Vector3d(0.1, -0.2, 0.3), bump, Eigen::Vector3d(0.1, 0.2, 1.0)));
  return g;
}

TEST(AffineRegionTest, FlatPlateIsOneRegionOfEveryCell) {
  const engine::CellStore store = BuildCells(Plate());
  ASSERT_EQ(store.regions().size(), 1u);
  EXPECT_EQ(store.regions()[0].numCells(), store.size());
  EXPECT_EQ(store.numSubdivisions(), 1);
}

TEST(AffineRegionTest, FlatPlateMatchesTheParallelogram) {
  const Geometry g = Plate();
  ReferenceGeometry reference(g);
  QueryMix mix;
  mix.on = 2000;
  mix.near = 8000;
  mix.mid = 5000;
  mix.far = 5000;
  const QuerySet q = MakeQueries(reference.cells(), 3, reference.size(), mix, 77);
  const Eigen::Matrix3d A = PlateMap();
  const Eigen::Vector3d o(0.1, -0.2, 0.3);  // the map at u = (0, 0)
  RunFamily("affine plate", g, q, [&](const double* p) {
    ReferenceAnswer answer;
    Eigen::Vector3d closest;
    answer.distance = ParallelogramDistance(o, A.col(0), A.col(1), Eigen::Vector3d(p[0], p[1], p[2]), &closest);
    answer.x = {closest[0], closest[1], closest[2]};
    return answer;
  });
}

double BandBump(int i, int, int) { return i >= 14 && i <= 18 ? 0.05 * (i - 13) : 0.0; }

TEST(AffineRegionTest, PlateWithACurvedBandMatchesBruteForce) {
  const Geometry g = Plate(BandBump);
  const engine::CellStore store = BuildCells(g);
  ASSERT_GE(store.regions().size(), 2u);
  for (const engine::AffineRegion& region : store.regions()) EXPECT_GE(region.numCells(), 2);
  // Every cell of a region is affine and the region's map reproduces it.
  std::int64_t inRegions = 0;
  for (const engine::AffineRegion& region : store.regions()) {
    const std::int64_t nu = static_cast<std::int64_t>(region.breaks[0].size()) - 1;
    const std::int64_t nv = static_cast<std::int64_t>(region.breaks[1].size()) - 1;
    for (std::int64_t j = 0; j < nv; ++j)
      for (std::int64_t i = 0; i < nu; ++i) {
        const std::int64_t cell = region.firstCell + i * region.cellStride[0] + j * region.cellStride[1];
        EXPECT_TRUE(store.solver(cell).isAffine());
        ++inRegions;
      }
  }
  EXPECT_LT(inRegions, store.size());
  EXPECT_GT(store.numSubdivisions(), static_cast<std::int64_t>(store.regions().size()));

  ReferenceGeometry reference(g);
  QueryMix mix;
  mix.on = 2000;
  mix.near = 8000;
  mix.mid = 4000;
  mix.far = 2000;
  const QuerySet q = MakeQueries(reference.cells(), 3, reference.size(), mix, 78);
  RunFamily("plate with a curved band", g, q, [&](const double* p) { return reference.Closest(p); });
}

TEST(AffineRegionTest, BlockVolumeMatchesTheParallelepiped) {
  std::mt19937_64 rng(43);
  Eigen::Matrix3d A;
  A << 1.0, 0.2, -0.1, 0.1, 0.8, 0.3, -0.2, 0.1, 1.2;
  const Eigen::Vector3d b(0.5, 0.25, -0.75);
  Geometry g;
  g.patches.push_back(AffineBSpline({1, 2, 2},
                                    {RandomKnots(1, 9, 100, true, rng), RandomKnots(2, 7, 3, true, rng),
                                     RandomKnots(2, 5, 100, true, rng)},
                                    A, b));
  const engine::CellStore store = BuildCells(g);
  ASSERT_EQ(store.regions().size(), 1u);

  ReferenceGeometry reference(g);
  QueryMix mix;
  mix.inside = 6000;
  mix.near = 4000;
  mix.mid = 3000;
  mix.far = 2000;
  const QuerySet q = MakeQueries(reference.cells(), 3, reference.size(), mix, 79);
  const Eigen::Matrix3d inverse = A.inverse();
  RunFamily("affine block volume", g, q, [&](const double* p) {
    const Eigen::Vector3d x(p[0], p[1], p[2]);
    const Eigen::Vector3d u = inverse * (x - b);
    ReferenceAnswer answer;
    if (u.minCoeff() >= 0 && u.maxCoeff() <= 1) {
      answer.distance = 0;
      answer.x = {x[0], x[1], x[2]};
      return answer;
    }
    // Outside: the nearest of the six faces.
    for (int d = 0; d < 3; ++d) {
      const int e1 = (d + 1) % 3, e2 = (d + 2) % 3;
      for (int side = 0; side < 2; ++side) {
        const Eigen::Vector3d o = b + side * A.col(d);
        Eigen::Vector3d closest;
        const double distance = ParallelogramDistance(o, A.col(e1), A.col(e2), x, &closest);
        if (distance < answer.distance) {
          answer.distance = distance;
          answer.x = {closest[0], closest[1], closest[2]};
        }
      }
    }
    return answer;
  });
}

}  // namespace
}  // namespace invmap::testing
