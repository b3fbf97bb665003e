// The cells of a geometry made only of linear triangle meshes in 3D, kept as
// what a mesh is: one array of vertices and one of corner indices. A
// triangle is an affine simplex, answered in closed form from its three
// vertices, so it needs no per-cell solver, net, shape or origin; on a large
// mesh those cost about 700 bytes per triangle (docs/limitations.md#memory).
#pragma once

#include <cstdint>
#include <vector>

#include "invmap/invmap.h"

namespace invmap::engine {

/// The triangles of every patch, in patch order (patch p's are
/// [patchFirst[p], patchFirst[p + 1])). Immutable after Build.
class MeshTriangles {
 public:
  /// True when every patch of `geometry` is a mesh of linear triangles in
  /// 3D whose vertices a 32-bit index reaches: the geometries Build takes.
  static bool Applies(const Geometry& geometry);
  /// Copies the vertices and corners of every patch. Precondition:
  /// Applies(geometry) and ValidateGeometry(geometry) found no problem.
  void Build(const Geometry& geometry);
  /// The same triangles, taken from `geometry` instead of copied: a single
  /// patch's vertex array is moved in, and each patch's arrays are freed as
  /// soon as they are consumed (the 64-bit indices once their 32-bit
  /// corners are made), so the geometry as read is gone before the tree's
  /// build allocates anything. Leaves the patches' points and cells empty.
  /// Same precondition as Build.
  void Take(Geometry&& geometry);

  bool empty() const { return patchFirst_.empty(); }
  std::int64_t size() const { return static_cast<std::int64_t>(corners_.size() / 3); }
  /// The first triangle of each patch, and size() last.
  const std::vector<std::int64_t>& patchFirst() const { return patchFirst_; }
  /// The patch of `cell`.
  std::int32_t PatchOf(std::int64_t cell) const;
  /// Vertex `v` (0, 1 or 2: the reference vertex where barycentric
  /// coordinate v is one) of `cell`: three coordinates.
  const double* Vertex(std::int64_t cell, int v) const {
    return vertices_.data() + 3 * static_cast<std::size_t>(corners_[3 * static_cast<std::size_t>(cell) + v]);
  }
  /// The index of vertex `v` of `cell` in vertices().
  std::int32_t Corner(std::int64_t cell, int v) const { return corners_[3 * static_cast<std::size_t>(cell) + v]; }
  /// Every patch's vertices in turn, 3 coordinates each.
  const double* vertices() const { return vertices_.data(); }
  /// The axis-aligned box of the triangle's vertices.
  void Box(std::int64_t cell, double* lo, double* hi) const;
  /// Heap memory of the arrays, in bytes.
  std::size_t MemoryBytes() const;

 private:
  std::vector<double> vertices_;          ///< 3 coordinates per vertex, every patch's in turn
  std::vector<std::int32_t> corners_;     ///< 3 per triangle, indices into vertices_
  std::vector<std::int64_t> patchFirst_;  ///< numPatches + 1 entries
};

}  // namespace invmap::engine
