// InversionOptions::maxDistance on partition-of-unity surfaces: a point at
// distance at most D is found for every D >= 0, as on cells (the gap band of
// engine/point_search.h). Points on the surface come from the independent
// evaluator of tests/support/pou_reference.h, so they lie on it only up to
// rounding: with D = 0 every one must still be found, at a distance within
// the band. Points off the surface are asked with D equal to the distance of
// the reference's closest point (a point of the surface, so no nearer than
// the true distance): every one found, no farther than D and the band.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <string>

#include "invmap/invmap.h"
#include "invmap/pou.h"
#include "tests/support/pou_meshes.h"
#include "tests/support/pou_reference.h"

namespace invmap {
namespace {

struct Surface {
  testing::TriangleMesh mesh;
  Patch patch;
  BuildResult built;
};

Surface Make(const testing::TriangleMesh& mesh, PouBase base) {
  Surface s{mesh, {}, {}};
  PouOptions options;
  options.base = base;
  const std::string error = BuildPouManifold(mesh.xyz.data(), mesh.numVertices(), mesh.triangles.data(),
                                             mesh.numTriangles(), options, &s.patch);
  EXPECT_EQ(error, "") << mesh.name;
  Geometry geometry;
  geometry.patches.push_back(s.patch);
  s.built = Manifold::Build(geometry);
  EXPECT_EQ(s.built.error, "") << mesh.name;
  return s;
}

TEST(PouMaxDistanceTest, PointsOnTheSurfaceAreFoundWithMaxDistanceZero) {
  std::mt19937_64 random(29);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const PouBase bases[] = {PouBase::Flat, PouBase::PnTriangles, PouBase::Loop};
  for (int b = 0; b < 3; ++b) {
    const Surface s = Make(b == 1 ? testing::Torus(8, 6, 2.0, 0.7) : testing::Bipyramid(4 + b), bases[b]);
    ASSERT_TRUE(s.built.manifold.valid());
    const testing::PouReference reference(s.patch.points, s.patch.cells, s.patch.degrees, s.patch.chartControlPoints);
    std::vector<double> points;
    for (int i = 0; i < 40; ++i) {
      // Chart centres (vertices of the mesh's charts) and random points of
      // the disk where the charts overlap most.
      const std::int64_t v = static_cast<std::int64_t>(random() % reference.numCharts());
      const double r = i % 8 == 0 ? 0.0 : 0.6 * reference.radius(v);
      double p[3];
      reference.Evaluate(v, {r * unit(random), r * unit(random)}, p);
      points.insert(points.end(), p, p + 3);
    }
    const double band = 1e-11 * s.mesh.diagonal();
    InversionOptions options;
    options.maxDistance = 0.0;
    Results results;
    ASSERT_EQ(s.built.manifold.Invert(PointsView::Interleaved(points.data(), points.size() / 3, 3), options, &results),
              Error::Ok);
    for (std::size_t i = 0; i < points.size() / 3; ++i) {
      const std::string where = s.mesh.name + " point " + std::to_string(i);
      ASSERT_EQ(results.status[i], Status::Found) << where;
      EXPECT_LE(results.distance[i], band) << where;
    }
  }
}

TEST(PouMaxDistanceTest, PointsAtDistanceDAreFoundWithMaxDistanceD) {
  std::mt19937_64 random(31);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Surface s = Make(testing::Bipyramid(5), PouBase::Loop);
  ASSERT_TRUE(s.built.manifold.valid());
  const testing::PouReference reference(s.patch.points, s.patch.cells, s.patch.degrees, s.patch.chartControlPoints);
  const double size = s.mesh.diagonal();
  const double band = 1e-11 * size;
  for (int i = 0; i < 12; ++i) {
    const std::int64_t v = static_cast<std::int64_t>(random() % reference.numCharts());
    const double r = 0.6 * reference.radius(v);
    double p[3], d[3] = {unit(random), unit(random), unit(random)};
    reference.Evaluate(v, {r * unit(random), r * unit(random)}, p);
    const double length = std::hypot(d[0], d[1], d[2]);
    const double offset = (i % 3 == 0 ? 1e-9 : i % 3 == 1 ? 0.01 : 0.2) * size;
    double x[3];
    for (int c = 0; c < 3; ++c) x[c] = p[c] + offset * d[c] / length;
    std::int64_t chart;
    std::complex<double> at;
    const double reachable = reference.Closest(x, &chart, &at);
    InversionOptions options;
    options.maxDistance = reachable;
    Results results;
    ASSERT_EQ(s.built.manifold.Invert(PointsView::Interleaved(x, 1, 3), options, &results), Error::Ok);
    const std::string where = "point " + std::to_string(i) + " at " + std::to_string(reachable);
    ASSERT_EQ(results.status[0], Status::Found) << where;
    EXPECT_LE(results.distance[0], reachable + band) << where;
    // A smaller D than the true distance (the reference's, less more than
    // its accuracy) leaves the point none.
    if (reachable > 1e-6 * size) {
      options.maxDistance = reachable - 1e-6 * size;
      ASSERT_EQ(s.built.manifold.Invert(PointsView::Interleaved(x, 1, 3), options, &results), Error::Ok);
      EXPECT_EQ(results.status[0], Status::None) << where;
    }
  }
}

}  // namespace
}  // namespace invmap
