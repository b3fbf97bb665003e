#include "engine/mesh_triangles.h"

#include <algorithm>
#include <limits>

namespace invmap::engine {

bool MeshTriangles::Applies(const Geometry& geometry) {
  if (geometry.dimension != 3 || geometry.patches.empty()) return false;
  std::size_t vertices = 0;
  for (const Patch& patch : geometry.patches) {
    if (patch.kind != Patch::Kind::Mesh || patch.cell != CellType::Tri) return false;
    vertices += patch.points.size() / 3;
  }
  return vertices <= static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max());
}

void MeshTriangles::Build(const Geometry& geometry) {
  std::size_t numVertices = 0, numCorners = 0;
  for (const Patch& patch : geometry.patches) {
    numVertices += patch.points.size();
    numCorners += patch.cells.size();
  }
  vertices_.clear();
  corners_.clear();
  patchFirst_.clear();
  vertices_.reserve(numVertices);
  corners_.reserve(numCorners);
  patchFirst_.reserve(geometry.patches.size() + 1);
  for (const Patch& patch : geometry.patches) {
    patchFirst_.push_back(size());
    // A triangle's finite-element vertex order is its Bezier net's.
    const auto base = static_cast<std::int64_t>(vertices_.size() / 3);
    for (const std::int64_t index : patch.cells) corners_.push_back(static_cast<std::int32_t>(base + index));
    vertices_.insert(vertices_.end(), patch.points.begin(), patch.points.end());
  }
  patchFirst_.push_back(size());
}

std::int32_t MeshTriangles::PatchOf(std::int64_t cell) const {
  // The last patch whose first triangle is at or before `cell` (empty
  // patches share their first index with the next one).
  const auto after = std::upper_bound(patchFirst_.begin(), patchFirst_.end() - 1, cell);
  return static_cast<std::int32_t>(after - patchFirst_.begin() - 1);
}

void MeshTriangles::Box(std::int64_t cell, double* lo, double* hi) const {
  for (int v = 0; v < 3; ++v) {
    const double* x = Vertex(cell, v);
    for (int k = 0; k < 3; ++k) {
      lo[k] = v == 0 ? x[k] : std::min(lo[k], x[k]);
      hi[k] = v == 0 ? x[k] : std::max(hi[k], x[k]);
    }
  }
}

std::size_t MeshTriangles::MemoryBytes() const {
  return vertices_.capacity() * sizeof(double) + corners_.capacity() * sizeof(std::int32_t) +
         patchFirst_.capacity() * sizeof(std::int64_t);
}

}  // namespace invmap::engine
