// The affine segments, triangles and tetrahedra among a BVH's items, with
// their vertices copied in the BVH's leaf order: the cells of a leaf lie
// side by side, so the search's closed-form solves (7.3.2.2) read one array
// in order instead of each cell's solver and its scattered control points.
// On a triangle mesh of a million cells this is most of the search's memory
// traffic.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/bvh_build.h"
#include "engine/cell_store.h"

namespace invmap::engine {

/// Item-indexed (BVH leaf order) vertex copies; every item gets a slot of
/// the largest simplex's size once any item is a simplex, so a mixed geometry
/// pays about 100 bytes for each of its curved cells too. A store of mesh
/// triangles alone (engine/mesh_triangles.h) gets no copies: its items keep
/// their three corner indices into the mesh's vertices (12 bytes, not 72).
/// Immutable after Build; safe to read from many threads.
class SimplexItems {
 public:
  /// Copies the vertices of every BVH item of `bvh` (built over the
  /// subdivisions of `store`) that is an affine simplex cell; nothing when
  /// there is none. `maxThreads` bounds the threads used (0 = all).
  void Build(const CellStore& store, const Bvh& bvh, int maxThreads = 0);

  /// True when no item is an affine simplex.
  bool empty() const { return cells_.empty(); }
  /// True when every item is an affine simplex (the search then never
  /// tests an item's own box).
  bool coversEveryItem() const { return !cells_.empty() && simplexCount_ == cells_.size(); }
  /// The cell of item `i` (BVH leaf order) when it is an affine simplex, else -1.
  std::int64_t cell(int i) const { return cells_.empty() ? -1 : cells_[i]; }
  /// The item of `cell` when it is an affine simplex item, else -1.
  int item(std::int64_t cell) const { return itemOfCell_.empty() ? -1 : itemOfCell_[cell]; }
  /// Parameter dimension (1, 2 or 3) of item `i`, an affine simplex.
  int paramDim(int i) const { return paramDims_[i]; }
  /// Vertex `v` of item `i`, an affine simplex (v <= paramDim(i), in the
  /// order of its reference vertices): ambient-dimension coordinates.
  const double* Vertex(int i, int v) const {
    return meshVertices_ ? meshVertices_ + 3 * static_cast<std::size_t>(corners_[3 * static_cast<std::size_t>(i) + v])
                         : vertices_.data() + static_cast<std::size_t>(i) * stride_ + v * dimension_;
  }
  /// Mesh triangles alone: the mesh's vertices and every item's three
  /// corners (indices into them, Bvh::Items() order); null otherwise.
  const double* meshVertices() const { return meshVertices_; }
  const std::int32_t* corners() const { return meshVertices_ ? corners_.data() : nullptr; }
  /// The vertices of item `i` side by side (paramDim(i) + 1 points), when
  /// they are copied (not for a store of mesh triangles alone).
  const double* vertices(int i) const { return vertices_.data() + static_cast<std::size_t>(i) * stride_; }
  /// Requests the memory of items [first, first + count) (a leaf's) from
  /// the cache, for reading soon.
  void Prefetch(int first, int count) const {
    __builtin_prefetch(&cells_[first]);
    __builtin_prefetch(&paramDims_[first]);
    const char* begin = meshVertices_ ? reinterpret_cast<const char*>(&corners_[3 * static_cast<std::size_t>(first)])
                                      : reinterpret_cast<const char*>(vertices(first));
    const char* end = meshVertices_ ? reinterpret_cast<const char*>(&corners_[3 * static_cast<std::size_t>(first + count)])
                                    : reinterpret_cast<const char*>(vertices(first + count));
    for (const char* line = begin; line < end; line += 64) __builtin_prefetch(line);
  }
  /// Heap memory of the copies, in bytes.
  std::size_t MemoryBytes() const;

 private:
  std::vector<std::int32_t> cells_;  ///< per item: its cell, or -1 (a BVH has at most 2^31 items)
  std::vector<std::int32_t> itemOfCell_;  ///< per cell of the store: its item, or -1
  std::vector<std::int8_t> paramDims_;
  std::vector<double> vertices_;  ///< stride_ doubles per item (no mesh triangles)
  int stride_ = 0;
  int dimension_ = 3;
  /// Mesh triangles alone: their vertex array (the store's, which moving
  /// the store keeps in place) and the corners of every item (3 per item,
  /// indices into it); null and empty otherwise.
  const double* meshVertices_ = nullptr;
  std::vector<std::int32_t> corners_;
  std::size_t simplexCount_ = 0;
};

}  // namespace invmap::engine
