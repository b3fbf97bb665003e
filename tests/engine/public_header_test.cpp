// The public header stands alone: it is included first and nothing internal
// is, and its basic contract holds.
#include "invmap/invmap.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

TEST(PublicHeader, BuildsAndInvertsWithThePublicTypesOnly) {
  invmap::Geometry geometry;
  geometry.dimension = 2;
  invmap::Patch segment;
  segment.kind = invmap::Patch::Kind::Mesh;
  segment.cell = invmap::CellType::Line;
  segment.points = {0, 0, 2, 0};
  segment.cells = {0, 1};
  geometry.patches.push_back(segment);
  invmap::BuildResult built = invmap::Manifold::Build(geometry);
  ASSERT_TRUE(built.error.empty()) << built.error;
  const float points[] = {0.5f, 1.0f, 3.0f, 0.0f};
  invmap::Results results;
  ASSERT_EQ(built.manifold.Invert(invmap::PointsView::Interleaved(points, 2, 2), {}, &results), invmap::Error::Ok);
  EXPECT_EQ(results.status[0], invmap::Status::Found);
  EXPECT_DOUBLE_EQ(results.distance[0], 1.0);
  EXPECT_DOUBLE_EQ(results.params[0], 0.25);
  EXPECT_TRUE(std::isnan(results.params[1]));
  EXPECT_DOUBLE_EQ(results.distance[1], 1.0);
  EXPECT_DOUBLE_EQ(results.closest[3], 2.0);  // 3 values per point, even in 2D
}

TEST(PublicHeader, MisuseIsAnErrorNotACrash) {
  invmap::Manifold empty;
  invmap::Results results;
  const double p[3] = {0, 0, 0};
  std::string message;
  EXPECT_EQ(empty.Invert(invmap::PointsView::Interleaved(p, 1, 3), {}, &results, &message),
            invmap::Error::InvalidArgument);
  EXPECT_FALSE(message.empty());
  invmap::Geometry geometry;
  // No cells: an error, not a geometry every point is "none" against.
  EXPECT_FALSE(invmap::Manifold::Build(geometry).error.empty());
  invmap::Patch triangle;
  triangle.kind = invmap::Patch::Kind::Mesh;
  triangle.cell = invmap::CellType::Tri;
  triangle.points = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  triangle.cells = {0, 1, 2};
  geometry.patches.push_back(triangle);
  invmap::BuildResult built = invmap::Manifold::Build(geometry);
  ASSERT_TRUE(built.error.empty()) << built.error;
  EXPECT_EQ(built.manifold.Invert(invmap::PointsView::Interleaved(p, 1, 2), {}, &results, &message),
            invmap::Error::InvalidArgument);  // 2D points, 3D geometry
  EXPECT_EQ(built.manifold.Invert(invmap::PointsView::Interleaved(p, 1, 3), {}, nullptr, &message),
            invmap::Error::InvalidArgument);
  invmap::InversionOptions negative;
  negative.maxDistance = -1.0;
  EXPECT_EQ(built.manifold.Invert(invmap::PointsView::Interleaved(p, 1, 3), negative, &results, &message),
            invmap::Error::InvalidArgument);
  geometry.dimension = 4;
  EXPECT_FALSE(invmap::Manifold::Build(geometry).error.empty());
}

}  // namespace
