// The partition-of-unity surfaces of a geometry (patches of kind
// PouManifold, include/invmap/pou.h): built next to the Bezier cells of the
// CellStore, which holds none of theirs, and searched after them. Each
// surface's pieces (pou/pieces.h) get a BVH from the engine's builder,
// collapsed to the wide tree with the pieces' oriented boxes; a query
// visits them nearest first and searches each (pou/piece_search.h); its best
// answer over the other patches is the cut-off they must beat.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "engine/bvh_build.h"
#include "engine/wide_bvh.h"
#include "engine/query_points.h"
#include "invmap/invmap.h"
#include "pou/pieces.h"
#include "pou/pou_surface.h"

namespace invmap::engine {

class PouPatches {
 public:
  /// Builds every PouManifold patch of `geometry`. Returns an error message
  /// naming the patch and field, or an empty string.
  std::string Build(const Geometry& geometry, int maxThreads);

  bool empty() const { return surfaces_.empty(); }
  /// Charts of `patch` when it is a pou_manifold, else -1.
  std::int64_t NumCells(std::size_t patch) const;
  /// A point of chart `cell` of `patch` (a pou_manifold): `sample`'s first two
  /// values in [0, 1] pick a point of the disk of radius R / sqrt(3) (where the
  /// chart's bump is the largest). False for indices out of range.
  bool PointAt(std::size_t patch, std::int64_t cell, const double sample[3], double params[3], double point[3]) const;
  /// Adds the charts (cells by shape "pou chart DxD") and their bounds.
  void AddInfo(ManifoldInfo* info) const;
  std::size_t MemoryBytes() const;
  /// Replaces each point's result by a closer point of the surfaces, if any
  /// (by more than the surfaces' tolerance), certified as in pou/piece_search.h.
  void Invert(const QueryPoints& points, const InversionOptions& options, Results* results) const;

 private:
  struct Surface {
    std::size_t patch = 0;
    pou::PouSurface surface;
    pou::PieceSet pieces;
    Bvh bvh;
    WideBvh wide;  ///< With each piece's oriented box (pou/pieces.h).
    double tolerance = 0.0;
  };
  const Surface* Find(std::size_t patch) const;

  std::vector<std::unique_ptr<Surface>> surfaces_;
};

}  // namespace invmap::engine
