// The library API in a few lines: build a geometry in memory (a curved
// quadratic Bezier triangle and a B-spline curve), invert a batch of points,
// read the results. Build: link invmap::invmap; include only invmap/invmap.h.
#include <cstdio>
#include <vector>

#include "invmap/invmap.h"

int main() {
  invmap::Geometry geometry;
  geometry.dimension = 3;

  invmap::Patch triangle;  // a quadratic Bezier triangle, bulging in z
  triangle.kind = invmap::Patch::Kind::Bezier;
  triangle.cell = invmap::CellType::Tri;
  triangle.degrees = {2};
  // Control points (0,0) (1,0) (2,0) (0,1) (1,1) (0,2) in units of 1/2 (docs/formats.md section 1).
  triangle.points = {0, 0, 0, 0.5, 0, 0.3, 1, 0, 0, 0, 0.5, 0.3, 0.5, 0.5, 0.3, 0, 1, 0};
  geometry.patches.push_back(triangle);

  invmap::Patch curve;  // a cubic B-spline curve with one interior knot
  curve.kind = invmap::Patch::Kind::BSpline;
  curve.degrees = {3};
  curve.knots = {{0, 0, 0, 0, 0.5, 1, 1, 1, 1}};
  curve.counts = {5};
  curve.points = {0, 0, 1, 0.5, 0.5, 1.5, 1, 0, 1, 1.5, -0.5, 1.5, 2, 0, 1};
  geometry.patches.push_back(curve);

  invmap::BuildResult built = invmap::Manifold::Build(geometry);
  if (!built.error.empty()) {
    std::fprintf(stderr, "invalid geometry: %s\n", built.error.c_str());
    return 1;
  }
  const std::vector<double> points = {0.3, 0.3, 1.0, 1.2, 0.1, 1.4, 5.0, 5.0, 5.0};
  invmap::Results results;
  std::string message;
  if (built.manifold.Invert(invmap::PointsView::Interleaved(points.data(), 3, 3), {}, &results, &message) !=
      invmap::Error::Ok) {
    std::fprintf(stderr, "%s\n", message.c_str());
    return 1;
  }
  for (int i = 0; i < 3; ++i) {
    std::printf("point %d: patch %d cell %lld params (%g, %g) closest (%g, %g, %g) distance %g\n", i,
                results.patch[i], static_cast<long long>(results.cell[i]), results.params[3 * i],
                results.params[3 * i + 1], results.closest[3 * i], results.closest[3 * i + 1],
                results.closest[3 * i + 2], results.distance[i]);
  }
  return 0;
}
