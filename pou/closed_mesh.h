// The topology a partition-of-unity surface is glued from: a closed,
// oriented, manifold triangle mesh, with each vertex's neighbours in
// counter-clockwise order (the gluing data of docs/manifold.md).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace invmap::pou {

/// A validated closed triangle mesh. Vertex v's neighbours u_0 .. u_{n-1}
/// (n its valence) are listed counter-clockwise, that is in the order the
/// triangles' orientation turns around v: triangle i of the star is
/// (v, u_i, u_{i+1}) up to a cyclic shift. u_0 is the vertex that follows v
/// in the first triangle (lowest index) that contains v; this rule fixes the
/// orientation of every chart (neighbour i sits at angle 2 pi i / n in the
/// p-domain of v), so a surface file depends on it.
class ClosedMesh {
 public:
  /// Checks `triangles` (3 vertex indices each, 0-based) over `numVertices`
  /// vertices at `xyz` and builds the rings. Returns an empty string, or a
  /// message naming the offending vertex, edge or triangle (0-based indices):
  /// a vertex coordinate that is not finite, an index out of range, a triangle that repeats a vertex or has zero
  /// area, an edge used by one triangle (a boundary) or by more than two
  /// (non-manifold), two triangles that run along an edge in the same
  /// direction (inconsistent orientation), a vertex in no triangle, a vertex
  /// whose triangles form more than one fan (non-manifold), a vertex of
  /// valence below 3.
  std::string Build(const double* xyz, std::int64_t numVertices, const std::int64_t* triangles,
                    std::int64_t numTriangles);

  std::int64_t numVertices() const { return static_cast<std::int64_t>(ringStart_.size()) - 1; }
  std::int64_t numTriangles() const { return static_cast<std::int64_t>(triangles_.size() / 3); }
  const std::vector<std::int64_t>& triangles() const { return triangles_; }
  const double* position(std::int64_t v) const { return &xyz_[3 * v]; }
  const std::vector<double>& positions() const { return xyz_; }

  int valence(std::int64_t v) const { return static_cast<int>(ringStart_[v + 1] - ringStart_[v]); }
  /// Neighbour i of v (0 <= i < valence(v)).
  std::int64_t neighbor(std::int64_t v, int i) const { return ring_[ringStart_[v] + i]; }
  /// Triangle i of v's star: the triangle (v, u_i, u_{i+1}).
  std::int64_t starTriangle(std::int64_t v, int i) const { return ringTriangle_[ringStart_[v] + i]; }
  /// The index of v in the ring of its neighbour i (so neighbor(neighbor(v, i), j) == v).
  int mate(std::int64_t v, int i) const { return ringMate_[ringStart_[v] + i]; }
  /// Where v sits in triangle t (0, 1 or 2), or -1.
  int CornerOf(std::int64_t t, std::int64_t v) const;

 private:
  std::vector<double> xyz_;
  std::vector<std::int64_t> triangles_;
  std::vector<std::int64_t> ringStart_;
  std::vector<std::int64_t> ring_;
  std::vector<std::int64_t> ringTriangle_;
  std::vector<int> ringMate_;
};

}  // namespace invmap::pou
