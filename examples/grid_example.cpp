// The implicit-complex grids in a few lines: refine a tetrahedron grid of the
// unit cube for a sphere and a plane, extract their zero sets (the sphere,
// the plane and the circle where they meet) and measure how far the sphere's
// triangles are from the true sphere. Build: link invmap::invmap; include
// only invmap/implicit.h.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "invmap/implicit.h"

int main() {
  namespace implicit = invmap::implicit;
  const implicit::Vec3 center = {0.5, 0.5, 0.5};
  const double radius = 0.3;
  const std::vector<implicit::Function> functions = {implicit::Function::Sphere(center, radius),
                                                     implicit::Function::Plane({0.5, 0.5, 0.6}, {0, 0, 1})};
  implicit::GridOptions options;
  options.epsilon = 1e-3;  // every zero set within 1e-3 of its linear pieces
  const implicit::GridResult result =
      implicit::RefineGrid(implicit::SimplexMesh::Box({0, 0, 0}, {1, 1, 1}, 3, 2), functions, options);
  if (!result.error.empty()) {
    std::fprintf(stderr, "%s\n", result.error.c_str());
    return 1;
  }
  const implicit::ZeroSets zeroSets = implicit::ExtractZeroSets(result.grid, options);

  // The sphere's triangles are labelled (0, -1, -1, -1): function 0 alone.
  std::size_t sphereTriangles = 0;
  double farthest = 0;
  for (std::size_t t = 0; t < zeroSets.triangleLabels.size(); ++t) {
    if (zeroSets.triangleLabels[t][0] != 0 || zeroSets.triangleLabels[t][1] != -1) continue;
    ++sphereTriangles;
    for (int k = 0; k < 3; ++k) {
      const double* p = &zeroSets.vertices[3 * zeroSets.triangles[3 * t + k]];
      const double off = std::hypot(p[0] - center[0], p[1] - center[1], p[2] - center[2]) - radius;
      farthest = std::max(farthest, std::fabs(off));
    }
  }
  std::printf("grid: %lld cells, %lld active\n", static_cast<long long>(result.grid.stats.cells),
              static_cast<long long>(result.grid.stats.activeCells));
  std::printf("zero sets: %zu triangles (%zu on the sphere), %zu segments on the circle\n",
              zeroSets.triangleLabels.size(), sphereTriangles, zeroSets.segmentLabels.size());
  std::printf("sphere vertices at most %.2g from the true sphere (epsilon %g)\n", farthest, options.epsilon);
  return sphereTriangles > 0 && farthest <= options.epsilon ? 0 : 1;
}
