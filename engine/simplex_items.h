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
/// pays about 100 bytes for each of its curved cells too. Immutable after
/// Build; safe to read from many threads.
class SimplexItems {
 public:
  /// Copies the vertices of every BVH item of `bvh` (built over the
  /// subdivisions of `store`) that is an affine simplex cell; nothing when
  /// there is none.
  void Build(const CellStore& store, const Bvh& bvh);

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
  /// The vertices of item `i`, an affine simplex: paramDim(i) + 1 points of
  /// the ambient dimension, in the order of its reference vertices.
  const double* vertices(int i) const { return vertices_.data() + static_cast<std::size_t>(i) * stride_; }
  /// Requests the memory of items [first, first + count) (a leaf's) from
  /// the cache, for reading soon.
  void Prefetch(int first, int count) const {
    __builtin_prefetch(&cells_[first]);
    __builtin_prefetch(&paramDims_[first]);
    const char* begin = reinterpret_cast<const char*>(vertices(first));
    const char* end = reinterpret_cast<const char*>(vertices(first + count));
    for (const char* line = begin; line < end; line += 64) __builtin_prefetch(line);
  }
  /// Heap memory of the copies, in bytes.
  std::size_t MemoryBytes() const;

 private:
  std::vector<std::int64_t> cells_;
  std::vector<std::int32_t> itemOfCell_;  ///< per cell of the store: its item, or -1
  std::vector<std::int8_t> paramDims_;
  std::vector<double> vertices_;  ///< stride_ doubles per item
  int stride_ = 0;
  std::size_t simplexCount_ = 0;
};

}  // namespace invmap::engine
