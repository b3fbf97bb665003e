#include "tests/support/gap_contract.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <limits>

namespace invmap::testing {
namespace {

Results InvertAll(const Manifold& manifold, const std::vector<double>& points, double maxDistance) {
  InversionOptions options;
  options.threads = 1;
  options.maxDistance = maxDistance;
  Results results;
  EXPECT_EQ(manifold.Invert(PointsView::Interleaved(points.data(), points.size() / 3, 3), options, &results),
            Error::Ok);
  return results;
}

}  // namespace

void ExpectClosestPointsFoundAtZeroGap(const Manifold& manifold, const std::vector<double>& queries, double size) {
  const double inf = std::numeric_limits<double>::infinity();
  const std::size_t n = queries.size() / 3;
  const Results first = InvertAll(manifold, queries, inf);
  ASSERT_EQ(first.status.size(), n);
  std::vector<double> closest;
  std::vector<double> away;  // the queries clearly off the geometry
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_EQ(first.status[i], Status::Found) << "query " << i;
    closest.insert(closest.end(), &first.closest[3 * i], &first.closest[3 * i] + 3);
    if (first.distance[i] >= 1e-9 * size) away.insert(away.end(), &queries[3 * i], &queries[3 * i] + 3);
  }
  const Results unlimited = InvertAll(manifold, closest, inf);
  const Results zero = InvertAll(manifold, closest, 0.0);
  int missed = 0;
  std::size_t firstMissed = 0;
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_LE(unlimited.distance[i], 1e-11 * size) << "closest point " << i << " not on the geometry";
    if (zero.status[i] == Status::Found && zero.distance[i] <= 1e-11 * size) continue;
    if (missed++ == 0) firstMissed = i;
  }
  EXPECT_EQ(missed, 0) << "of " << n << " closest points re-inverted with a gap tolerance of 0, e.g. ("
                       << closest[3 * firstMissed] << ", " << closest[3 * firstMissed + 1] << ", "
                       << closest[3 * firstMissed + 2] << "), at " << unlimited.distance[firstMissed]
                       << " without a limit";
  const Results off = InvertAll(manifold, away, 0.0);
  int foundOff = 0;
  for (const Status s : off.status) foundOff += s != Status::None;
  EXPECT_EQ(foundOff, 0) << "of " << away.size() / 3 << " points at least 1e-9 of the size away, found with D = 0";
  EXPECT_GT(away.size(), queries.size() / 4) << "too few queries off the geometry to check";
}

}  // namespace invmap::testing
