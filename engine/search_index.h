// Everything a batch of queries searches, built once per geometry: the cells
// (CellStore), the BVH over their subdivisions, its 4-wide form with
// oriented boxes, the affine simplices' vertices in the BVH's leaf order, and
// the partition-of-unity surfaces (PouPatches), which have no Bezier cells.
#pragma once

#include <cstddef>

#include "engine/bvh_build.h"
#include "engine/cell_store.h"
#include "engine/pou_patches.h"
#include "engine/simplex_items.h"
#include "engine/wide_bvh.h"
#include "invmap/invmap.h"

namespace invmap::engine {

/// The search index of one geometry. Immutable once built; safe to read
/// from many threads; movable, not copyable.
class SearchIndex {
 public:
  /// Builds the index of `geometry`, each part from the finished ones before
  /// it: the cells, the BVH over their subdivisions' boxes (Embree's SAH
  /// builder), the wide BVH with oriented boxes fitted to the subdivisions'
  /// hull points, and the simplex items. Precondition:
  /// ValidateGeometry(geometry) found no problem
  /// (engine/geometry_validation.h). `maxThreads` bounds the threads used
  /// (0 = all).
  static SearchIndex Build(const Geometry& geometry, int maxThreads = 0);
  /// The same index, taking what it can from `geometry` instead of copying
  /// it: a geometry of triangle meshes alone gives up its vertex and index
  /// arrays (MeshTriangles::Take) before the tree is built; any other is
  /// read as by Build(const Geometry&) and left as it was.
  static SearchIndex Build(Geometry&& geometry, int maxThreads = 0);

  const CellStore& cells() const { return cells_; }
  /// Binary BVH over the subdivisions of cells() (CellStore::numSubdivisions).
  const Bvh& bvh() const { return bvh_; }
  /// The BVH collapsed to 4-wide nodes, with oriented boxes.
  const WideBvh& wideBvh() const { return wideBvh_; }
  /// The affine simplex items of bvh(), in its leaf order.
  const SimplexItems& simplices() const { return simplices_; }
  /// The pou_manifold patches, searched after the cells (InvertBatch).
  const PouPatches& pou() const { return pou_; }
  int dimension() const { return cells_.dimension(); }
  /// Heap memory of every part, in bytes.
  std::size_t MemoryBytes() const;

 private:
  SearchIndex(CellStore cells, Bvh bvh, WideBvh wideBvh, SimplexItems simplices, PouPatches pou);
  /// Builds everything after the cells: the trees, the simplex items and
  /// the partition-of-unity surfaces of `geometry`.
  static SearchIndex BuildOver(CellStore cells, const Geometry& geometry, int maxThreads);

  CellStore cells_;
  Bvh bvh_;
  WideBvh wideBvh_;
  SimplexItems simplices_;
  PouPatches pou_;
};

}  // namespace invmap::engine
