#include "engine/mesh_triangles.h"

#include <algorithm>
#include <limits>
#include <type_traits>
#include <utility>

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

namespace {

/// Copies the vertices and corners of every patch of `patches` into the
/// arrays; from a mutable patch list (MeshTriangles::Take) a single patch's
/// vertex array is moved instead, and each patch's arrays are freed once
/// consumed.
template <typename Patches>
void Fill(Patches& patches, std::vector<double>* vertices, std::vector<std::int32_t>* corners,
          std::vector<std::int64_t>* patchFirst) {
  constexpr bool take = !std::is_const_v<Patches>;
  std::size_t numVertices = 0, numCorners = 0;
  for (const Patch& patch : patches) {
    numVertices += patch.points.size();
    numCorners += patch.cells.size();
  }
  vertices->clear();
  corners->clear();
  patchFirst->clear();
  const bool moveVertices = take && patches.size() == 1;
  if (!moveVertices) vertices->reserve(numVertices);
  corners->reserve(numCorners);
  patchFirst->reserve(patches.size() + 1);
  std::int64_t base = 0;
  for (auto& patch : patches) {
    patchFirst->push_back(static_cast<std::int64_t>(corners->size() / 3));
    // A triangle's finite-element vertex order is its Bezier net's.
    for (const std::int64_t index : patch.cells) corners->push_back(static_cast<std::int32_t>(base + index));
    base += static_cast<std::int64_t>(patch.points.size() / 3);
    if constexpr (take) {
      std::vector<std::int64_t>().swap(patch.cells);
      if (moveVertices) {
        *vertices = std::move(patch.points);
      } else {
        vertices->insert(vertices->end(), patch.points.begin(), patch.points.end());
        std::vector<double>().swap(patch.points);
      }
    } else {
      vertices->insert(vertices->end(), patch.points.begin(), patch.points.end());
    }
  }
  patchFirst->push_back(static_cast<std::int64_t>(corners->size() / 3));
}

}  // namespace

void MeshTriangles::Build(const Geometry& geometry) { Fill(geometry.patches, &vertices_, &corners_, &patchFirst_); }

void MeshTriangles::Take(Geometry&& geometry) { Fill(geometry.patches, &vertices_, &corners_, &patchFirst_); }

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
