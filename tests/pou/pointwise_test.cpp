// InversionOptions::pointwise on partition-of-unity surfaces: a point's
// answer is a function of the point and the geometry only, bit for bit,
// whether it is inverted alone, in a batch or in another order
// (docs/limitations.md, "Answers that depend on the batch").
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>

#include "invmap/invmap.h"
#include "invmap/pou.h"
#include "tests/pou/pou_test_support.h"

namespace invmap {
namespace {

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(PouPointwiseTest, AnswersDoNotDependOnTheBatch) {
  for (const testing::TriangleMesh& m : {testing::Icosphere(1, 1.0), testing::Bipyramid(24)}) {
    testing::BuiltPou b;
    testing::BuildPou(m, PouBase::Loop, &b);
    if (::testing::Test::HasFatalFailure()) return;
    const Manifold& manifold = b.built.manifold;
    std::mt19937_64 random(3);
    std::normal_distribution<double> normal(0.0, 1.0);
    const int count = 120;
    std::vector<double> points, reversed(3 * count);
    for (int i = 0; i < 3 * count; ++i) points.push_back(1.2 * normal(random));
    for (int i = 0; i < count; ++i)
      for (int c = 0; c < 3; ++c) reversed[3 * (count - 1 - i) + c] = points[3 * i + c];
    InversionOptions pointwise;
    pointwise.pointwise = true;
    pointwise.threads = 1;
    Results batch, backwards;
    ASSERT_EQ(manifold.Invert(PointsView::Interleaved(points.data(), count, 3), pointwise, &batch), Error::Ok);
    ASSERT_EQ(manifold.Invert(PointsView::Interleaved(reversed.data(), count, 3), pointwise, &backwards),
              Error::Ok);
    for (int i = 0; i < count; ++i) {
      Results alone;
      ASSERT_EQ(manifold.Invert(PointsView::Interleaved(&points[3 * i], 1, 3), pointwise, &alone), Error::Ok);
      const std::string where = m.name + " point " + std::to_string(i);
      const int j = count - 1 - i;
      ASSERT_EQ(batch.status[i], Status::Found) << where;
      EXPECT_EQ(alone.status[0], batch.status[i]) << where;
      EXPECT_EQ(alone.cell[0], batch.cell[i]) << where;
      EXPECT_EQ(backwards.cell[j], batch.cell[i]) << where;
      EXPECT_TRUE(SameBits(alone.distance[0], batch.distance[i])) << where;
      EXPECT_TRUE(SameBits(backwards.distance[j], batch.distance[i])) << where;
      for (int c = 0; c < 2; ++c) {
        EXPECT_TRUE(SameBits(alone.params[c], batch.params[3 * i + c])) << where;
        EXPECT_TRUE(SameBits(backwards.params[3 * j + c], batch.params[3 * i + c])) << where;
      }
      for (int c = 0; c < 3; ++c) {
        EXPECT_TRUE(SameBits(alone.closest[c], batch.closest[3 * i + c])) << where;
        EXPECT_TRUE(SameBits(backwards.closest[3 * j + c], batch.closest[3 * i + c])) << where;
      }
    }
  }
}

}  // namespace
}  // namespace invmap
