// Every local minimum of a point's distance (LocalMinima) against an
// independent dense-sampling reference: none missed, none extra, each once,
// nearest first; minima on cell edges and across creases; max distance.
#include <gtest/gtest.h>

#include <random>

#include "tests/distance/distance_test_util.h"
#include "tests/support/distance_geometries.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

struct Found {
  double distance;
  std::array<double, 3> point;
};

std::vector<Found> Minima(const Manifold& manifold, const double* point, int dim, double maxDistance,
                          bool* certified) {
  InversionOptions options;
  options.maxDistance = maxDistance;
  LocalMinimaResults results;
  std::string message;
  EXPECT_EQ(LocalMinima(manifold, PointsView::Interleaved(point, 1, dim), options, &results, &message), Error::Ok)
      << message;
  std::vector<Found> out;
  for (std::int64_t r = results.offsets[0]; r < results.offsets[1]; ++r) {
    if (results.minima.status[r] != Status::Found) continue;
    out.push_back({results.minima.distance[r],
                   {results.minima.closest[3 * r], results.minima.closest[3 * r + 1], results.minima.closest[3 * r + 2]}});
  }
  *certified = results.certified[0] != 0;
  return out;
}

/// invmap's minima against the reference's for points around `geometry`.
void CompareMinima(const Geometry& geometry, const std::vector<std::array<double, 3>>& points, double maxDistance,
                   int divisions, int* total) {
  const auto model = BuildModel(geometry);
  const double size = GeometrySize(geometry);
  for (const auto& p : points) {
    SCOPED_TRACE("point " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]));
    bool certified = false;
    const std::vector<Found> found = Minima(model->manifold, p.data(), geometry.dimension, maxDistance, &certified);
    const std::vector<PairReferencePoint> reference =
        BruteForcePointMinima(geometry, p.data(), maxDistance, 1e-5 * size, divisions);
    EXPECT_TRUE(certified);
    // Nearest first, each once.
    for (std::size_t i = 1; i < found.size(); ++i) {
      EXPECT_LE(found[i - 1].distance, found[i].distance);
      for (std::size_t j = 0; j < i; ++j) EXPECT_GT(PointDistance(found[i].point.data(), found[j].point.data()), 1e-6 * size);
    }
    // None missed, none extra: the same points, the same distances.
    EXPECT_GE(found.size(), reference.size());
    for (const PairReferencePoint& r : reference) {
      bool matched = false;
      for (const Found& f : found) {
        matched = matched || (PointDistance(f.point.data(), r.point.data()) <= 1e-5 * size &&
                              std::abs(f.distance - PointDistance(r.point.data(), p.data())) <= 1e-9 * size);
      }
      EXPECT_TRUE(matched) << "the reference's minimum at " << r.point[0] << " " << r.point[1] << " " << r.point[2]
                           << " is missing";
    }
    for (const Found& f : found) {
      EXPECT_LE(f.distance, maxDistance);
      bool matched = false;
      for (const PairReferencePoint& r : reference) matched = matched || PointDistance(f.point.data(), r.point.data()) <= 1e-5 * size;
      // One the lattice missed (a dimple narrower than its step) must still
      // be a minimum as the tests' own evaluator sees it around the point.
      if (!matched) matched = VerifyLocalMinimum(geometry, p.data(), f.point.data(), 1e-12 * size);
      EXPECT_TRUE(matched) << "extra minimum at " << f.point[0] << " " << f.point[1] << " " << f.point[2];
    }
    *total += static_cast<int>(found.size());
  }
}

TEST(LocalMinima, WavyCurveHasSeveralMinima) {
  int total = 0;
  CompareMinima(WavyCurve(0.2, 3, 12), {{0.5, 0.0, 1.0}, {0.2, 0.3, 0.5}, {0.8, -0.2, -0.6}, {0.45, 0.05, 0.05}},
                10.0, 400, &total);
  EXPECT_GE(total, 10);  // the curve's crests: several minima per point
}

TEST(LocalMinima, WavySurfaceMinimaAcrossCells) {
  int total = 0;
  // An egg crate: seen from above, each crest within reach is a minimum,
  // and most lie on edges or corners of the 8 x 8 cells.
  CompareMinima(WavySurface(0.25, 2, 2, 8, false), {{0.5, 0.5, 0.5}, {0.3, 0.6, 0.8}, {0.25, 0.25, -0.5}}, 10.0, 40,
                &total);
  EXPECT_GE(total, 20);
}

TEST(LocalMinima, RationalSurfaceWithinMaxDistance) {
  int total = 0;
  CompareMinima(WavySurface(0.08, 2, 1, 5, true), {{0.5, 0.5, 0.4}, {0.2, 0.8, -0.3}}, 0.45, 48, &total);
  EXPECT_GE(total, 2);
}

TEST(LocalMinima, CreasesAndPatchesWithRepeatedKnots) {
  // Two patches with repeated interior knots (C0 and C1 creases), the
  // second rational and unclamped: minima on creases count only where the
  // distance grows into both sides.
  const Geometry geometry = WavySurfaces();
  double lo[3], hi[3];
  GeometryControlBox(geometry, lo, hi);
  std::vector<std::array<double, 3>> points;
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 4; ++i) {
    points.push_back({lo[0] + (hi[0] - lo[0]) * u(rng), lo[1] + (hi[1] - lo[1]) * u(rng),
                      lo[2] + (hi[2] - lo[2]) * u(rng)});
  }
  int total = 0;
  // Some of these minima are shallow dimples (the distance 1e-7 above its
  // least value a thousandth of a cell away), which no lattice resolves:
  // those are verified around the point itself.
  CompareMinima(geometry, points, 0.15 * GeometrySize(geometry), 24, &total);
  EXPECT_GE(total, 4);
}

TEST(LocalMinima, ConcentricCirclesOfATorusAndInvalidPoints) {
  // From (2, 0, 3), above the tube's core circle: the top of the tube below
  // is the one local minimum (elsewhere on the torus the distance falls
  // toward it).
  const auto torus = BuildModel(NurbsTorus({0, 0, 0}, 2.0, 0.7));
  const double points[] = {2.0, 0.0, 3.0, std::nan(""), 0.0, 0.0, 2.0, 0.0, 3.0};
  InversionOptions options;
  LocalMinimaResults results;
  ASSERT_EQ(LocalMinima(torus->manifold, PointsView::Interleaved(points, 3, 3), options, &results), Error::Ok);
  ASSERT_EQ(results.offsets.size(), 4u);
  ASSERT_EQ(results.offsets[1] - results.offsets[0], 1);
  EXPECT_EQ(results.minima.status[0], Status::Found);
  EXPECT_NEAR(results.minima.distance[0], 2.3, 1e-9);
  EXPECT_EQ(results.offsets[2] - results.offsets[1], 1);
  EXPECT_EQ(results.minima.status[results.offsets[1]], Status::Invalid);
  EXPECT_EQ(results.minima.distance[results.offsets[2]], results.minima.distance[0]);
  // Nothing within 2.
  options.maxDistance = 2.0;
  ASSERT_EQ(LocalMinima(torus->manifold, PointsView::Interleaved(points, 1, 3), options, &results), Error::Ok);
  ASSERT_EQ(results.offsets[1], 1);
  EXPECT_EQ(results.minima.status[0], Status::None);
}

}  // namespace
}  // namespace invmap::testing
