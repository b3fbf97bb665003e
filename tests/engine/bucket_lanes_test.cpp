// The lanes of one bucket, called directly: a bucket of points around one
// point of the geometry is mostly settled by the lanes (the batch's tests in
// curved_lanes_test.cpp cannot tell which path answered), and every answer
// they settle is the brute-force reference's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "engine/bucket_lanes.h"
#include "engine/search_index.h"
#include "engine/volume_lanes.h"
#include "tests/support/closest_reference.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

constexpr int kBucket = 32;

/// The points of one bucket: `base` first, then points within `spread` of it.
std::vector<double> BucketAround(const double* base, int dim, double spread, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> offset(-spread, spread);
  std::vector<double> coord(3 * kBucket, 0.0);  // structure of arrays
  for (int j = 0; j < kBucket; ++j) {
    for (int k = 0; k < dim; ++k) coord[k * kBucket + j] = base[k] + (j == 0 ? 0.0 : offset(rng));
  }
  return coord;
}

/// The store's index of the cell the reference answered in.
std::int64_t StoreCell(const engine::CellStore& store, const ReferenceAnswer& answer) {
  return store.patchFirstCell(static_cast<std::size_t>(answer.patch)) + answer.cell;
}

/// Buckets on curves or surfaces: at least `minSettled` of their points are
/// settled by the lanes, each as the reference.
void ExpectBucketLanesSettle(const Geometry& g, double spreadOfSize, double minSettled, std::uint64_t seed) {
  ReferenceGeometry reference(g);
  const engine::SearchIndex index = engine::SearchIndex::Build(g);
  const engine::CellStore& store = index.cells();
  const int dim = g.dimension;
  std::mt19937_64 rng(seed);
  QueryMix on;
  on.on = 40;
  const QuerySet bases = MakeQueries(reference.cells(), dim, reference.size(), on, seed);
  engine::BucketLanes lanes;
  int settled = 0, total = 0;
  for (std::size_t b = 0; b < bases.size(); ++b) {
    const std::vector<double> coord = BucketAround(bases.point(b), dim, spreadOfSize * reference.size(), rng);
    const double* columns[3] = {&coord[0], &coord[kBucket], dim == 3 ? &coord[2 * kBucket] : nullptr};
    // The first point's answer, as the per-point search leaves it.
    const double p0[3] = {coord[0], coord[kBucket], dim == 3 ? coord[2 * kBucket] : 0.0};
    engine::WarmStart first;
    first.cell = StoreCell(store, reference.Closest(p0));
    if (!engine::StartsBucketLanes(store, index.simplices(), first.cell)) continue;
    kernels::SolveWorkspace workspace;
    const kernels::CellSolveResult r0 = store.solver(first.cell).Solve(p0, nullptr, &workspace);
    std::copy(p0, p0 + 3, first.point);
    std::copy(r0.ref, r0.ref + 3, first.ref);
    std::copy(r0.closest, r0.closest + 3, first.closest);
    engine::SolveBucketInLanes(store, index.wideBvh(), index.bvh(), index.simplices(), columns, kBucket, first,
                               std::numeric_limits<double>::infinity(), &lanes);
    EXPECT_FALSE(lanes.settled[0]);
    for (int j = 1; j < kBucket; ++j) {
      ++total;
      if (!lanes.settled[j]) continue;
      ++settled;
      const double p[3] = {coord[j], coord[kBucket + j], dim == 3 ? coord[2 * kBucket + j] : 0.0};
      const ReferenceAnswer expected = reference.Closest(p);
      ASSERT_GE(lanes.cell[j], 0) << "bucket " << b << " point " << j;
      EXPECT_NEAR(lanes.result[j].distance, expected.distance, 1e-9 * reference.size())
          << "bucket " << b << " point " << j;
      double d2 = 0.0;
      for (int k = 0; k < dim; ++k) d2 += (lanes.result[j].closest[k] - p[k]) * (lanes.result[j].closest[k] - p[k]);
      EXPECT_NEAR(std::sqrt(d2), lanes.result[j].distance, 1e-9 * reference.size());
    }
  }
  ASSERT_GT(total, 0);
  EXPECT_GE(settled, minSettled * total) << settled << " of " << total << " settled by the lanes";
}

TEST(BucketLanesTest, SurfacePointsAreSettledAsTheReference) {
  ExpectBucketLanesSettle(WavySurfaces(), 0.005, 0.5, 2811);
}

TEST(BucketLanesTest, CurvePointsAreSettledAsTheReference) {
  ExpectBucketLanesSettle(BSplineCurves(3), 0.005, 0.5, 2812);
  ExpectBucketLanesSettle(BSplineCurves(2), 0.005, 0.5, 2813);
}

TEST(VolumeLanesTest, InsidePointsAreSettledAsTheReference) {
  const Geometry g = QuadraticMesh(false);
  ReferenceGeometry reference(g);
  const engine::SearchIndex index = engine::SearchIndex::Build(g);
  const engine::CellStore& store = index.cells();
  std::mt19937_64 rng(2814);
  QueryMix inside;
  inside.inside = 40;
  const QuerySet bases = MakeQueries(reference.cells(), 3, reference.size(), inside, 2814);
  engine::VolumeLanes lanes;
  int settled = 0, total = 0;
  for (std::size_t b = 0; b < bases.size(); ++b) {
    const std::vector<double> coord = BucketAround(bases.point(b), 3, 0.01 * reference.size(), rng);
    const double* columns[3] = {&coord[0], &coord[kBucket], &coord[2 * kBucket]};
    const double p0[3] = {coord[0], coord[kBucket], coord[2 * kBucket]};
    const std::int64_t start = StoreCell(store, reference.Closest(p0));
    ASSERT_TRUE(engine::IsLaneTetrahedron(store, start));
    engine::SolveInsideByLanes(store, columns, kBucket, start, 8, &lanes);
    EXPECT_EQ(lanes.cell[0], -1);
    for (int j = 1; j < kBucket; ++j) {
      const double p[3] = {coord[j], coord[kBucket + j], coord[2 * kBucket + j]};
      const ReferenceAnswer expected = reference.Closest(p);
      // Outside the mesh (the offsets cross its boundary): the walk may stop anywhere.
      if (expected.distance > 1e-9 * reference.size()) continue;
      ++total;
      if (lanes.cell[j] < 0) continue;
      ++settled;
      // Inside: the point is its own closest point.
      EXPECT_LE(lanes.result[j].distance, 1e-9 * reference.size()) << "bucket " << b << " point " << j;
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(lanes.result[j].closest[k], p[k], 1e-9 * reference.size());
    }
  }
  ASSERT_GT(total, 0);
  EXPECT_GE(settled, 0.75 * total) << settled << " of " << total << " settled by the lanes";
}

}  // namespace
}  // namespace invmap::testing
