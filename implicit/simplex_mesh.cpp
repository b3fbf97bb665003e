// SimplexMesh::Box: the initial grids of `invmap grid --box`.
#include <cstdint>

#include "invmap/implicit.h"

namespace invmap::implicit {
namespace {

// The 6 tetrahedra of Freudenthal's (Kuhn's) subdivision of the unit cube:
// each walks from corner 0 to corner 7 along the cube's main diagonal, one
// axis at a time (corner bit 0 = x, bit 1 = y, bit 2 = z). Neighbouring
// cubes cut their shared faces along the same diagonal, so the mesh is
// conforming. The axis order is chosen so each tetrahedron has a positive
// volume.
constexpr int kCubeTets[6][4] = {
    {0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7}, {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7},
};

// The 2 triangles of a square (corner bit 0 = x, bit 1 = y), counter-clockwise.
constexpr int kSquareTriangles[2][3] = {{0, 1, 3}, {0, 3, 2}};

}  // namespace

SimplexMesh SimplexMesh::Box(const Vec3& lo, const Vec3& hi, int dimension, int resolution) {
  SimplexMesh mesh;
  mesh.dimension = dimension;
  const int n = resolution;
  const int axes = dimension;
  const std::int64_t perAxis = n + 1;
  const std::int64_t layers = axes == 3 ? perAxis : 1;
  for (std::int64_t k = 0; k < layers; ++k) {
    for (std::int64_t j = 0; j < perAxis; ++j) {
      for (std::int64_t i = 0; i < perAxis; ++i) {
        const std::int64_t index[3] = {i, j, k};
        for (int a = 0; a < 3; ++a) {
          if (a >= axes) {
            mesh.vertices.push_back(0);
            continue;
          }
          // Exact at both ends: lo + (hi - lo) * 1 may differ from hi.
          const double t = static_cast<double>(index[a]) / n;
          mesh.vertices.push_back(index[a] == n ? hi[a] : lo[a] + (hi[a] - lo[a]) * t);
        }
      }
    }
  }
  auto vertexOf = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
    return static_cast<std::uint32_t>((k * perAxis + j) * perAxis + i);
  };
  for (std::int64_t k = 0; k < (axes == 3 ? n : 1); ++k) {
    for (std::int64_t j = 0; j < n; ++j) {
      for (std::int64_t i = 0; i < n; ++i) {
        std::uint32_t corner[8];
        for (int c = 0; c < 8; ++c) corner[c] = vertexOf(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
        if (axes == 3) {
          for (const auto& tet : kCubeTets)
            for (int v : tet) mesh.cells.push_back(corner[v]);
        } else {
          for (const auto& triangle : kSquareTriangles)
            for (int v : triangle) mesh.cells.push_back(corner[v]);
        }
      }
    }
  }
  return mesh;
}

}  // namespace invmap::implicit
