// The cells of a manifold: every patch turned into Bezier cells, with their
// solvers (bounds, precomputed distance nets) and the way back to the patch.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/check.h"
#include "engine/affine_regions.h"
#include "engine/tet_adjacency.h"
#include "invmap/invmap.h"
#include "kernels/cell_solver.h"

namespace invmap::engine {

/// Where a cell came from and how its reference coordinates map to the
/// parameters reported for it: param_i = paramLo[i] + paramScale[i] * ref_i
/// (knot values for B-spline cells; identity for Bezier and mesh cells).
struct CellOrigin {
  std::int32_t patch = 0;
  /// The cell's type: its reference domain and number of parameters.
  kernels::CellType type = kernels::CellType::Line;
  std::int64_t indexInPatch = 0;
  double paramLo[3] = {0, 0, 0};
  double paramScale[3] = {1, 1, 1};
  /// True when the patch's cells tile one parameter domain (B-spline
  /// patches), so a parameter of one cell means a place near another.
  bool sharedParameters = false;
  /// With sharedParameters: the cell's place in its patch's grid of spans.
  std::array<std::int32_t, 3> span{0, 0, 0};
};

/// All cells of a geometry. Immutable after Build; safe to read from many threads.
class CellStore {
 public:
  /// Validates `geometry` and builds its cells. Returns an empty string on
  /// success, otherwise a message naming the patch and the field
  /// ("patch 3: cells[12]: vertex index 99 out of range [0, 40)").
  /// `maxThreads` bounds the threads used to precompute the cells (0 = all).
  std::string Build(const Geometry& geometry, int maxThreads);

  int dimension() const { return dimension_; }
  std::int64_t size() const { return static_cast<std::int64_t>(solvers_.size()); }
  const kernels::CellSolver& solver(std::int64_t cell) const {
    INVMAP_ASSERT(cell >= 0 && cell < size(), "cell " << cell << " not in [0, " << size() << ")");
    return solvers_[cell];
  }
  const CellOrigin& origin(std::int64_t cell) const {
    INVMAP_ASSERT(cell >= 0 && cell < size(), "cell " << cell << " not in [0, " << size() << ")");
    return origins_[cell];
  }
  std::size_t numPatches() const { return numPatches_; }
  /// True when some cell is a volume (paramDim == dimension), whose exact
  /// inside hits the search tries first.
  bool hasVolumeCells() const { return hasVolumeCells_; }
  /// Index of the first cell of `patch` (cells of a patch are contiguous);
  /// patchFirstCell(numPatches()) == size().
  std::int64_t patchFirstCell(std::size_t patch) const { return patchFirst_[patch]; }
  /// Heap memory of the cells: control points, weights, solvers and their nets.
  std::size_t MemoryBytes() const;

  /// Affine regions of the B-spline patches (engine/affine_regions.h).
  const std::vector<AffineRegion>& regions() const { return regions_; }
  /// Subdivisions (algorithm 6): what the BVH holds and the search visits:
  /// every affine region once, and every cell outside a region.
  std::int64_t numSubdivisions() const { return static_cast<std::int64_t>(subdivisions_.size()); }
  /// True when subdivision `s` is an affine region.
  bool isRegion(std::int64_t s) const { return subdivisions_[s] < 0; }
  /// The cell of a subdivision that is a cell.
  std::int64_t subdivisionCell(std::int64_t s) const { return subdivisions_[s]; }
  /// The region of a subdivision that is a region.
  const AffineRegion& subdivisionRegion(std::int64_t s) const { return regions_[-1 - subdivisions_[s]]; }
  /// The cell of subdivision `s` when it is an affine segment, triangle or
  /// tetrahedron (solved in closed form), else -1.
  std::int64_t affineSimplexCell(std::int64_t s) const {
    return !isRegion(s) && solvers_[subdivisions_[s]].isAffineSimplex() ? subdivisions_[s] : -1;
  }
  /// True when `cell` belongs to an affine region (it is then searched only
  /// as part of its region).
  bool inRegion(std::int64_t cell) const { return regionOfCell_[cell] >= 0; }
  /// The cell of the same B-spline patch `step[d]` spans (-1, 0 or +1)
  /// away from `cell` along each of its parameter directions d, or -1 when
  /// that leaves the patch or `cell` is not a B-spline patch's.
  std::int64_t SplineNeighbor(std::int64_t cell, const int* step) const;
  /// Face neighbours of the tetrahedral cells (empty without tetrahedra).
  const TetAdjacency& tetAdjacency() const { return tetAdjacency_; }
  /// Bounds of a subdivision's cells.
  const double* subdivisionBoxLo(std::int64_t s) const {
    return isRegion(s) ? subdivisionRegion(s).boxLo : solvers_[subdivisions_[s]].boxLo();
  }
  const double* subdivisionBoxHi(std::int64_t s) const {
    return isRegion(s) ? subdivisionRegion(s).boxHi : solvers_[subdivisions_[s]].boxHi();
  }
  /// Appends to `xyz` (3 coordinates per point, 0 as the third in 2D) points
  /// whose convex hull holds subdivision `s`: a cell's control points
  /// (weights are positive), a region's parameter-box corners mapped by its
  /// affine map. Nothing for volumes: an oriented box (engine/oriented_box.h)
  /// around a solid prunes little that its axis-aligned box does not.
  void SubdivisionHullPoints(std::int64_t s, std::vector<double>* xyz) const;

 private:
  /// Appends one Bezier cell (control points copied) and its origin.
  void AddCell(const kernels::CellShape& shape, const double* points, const double* weights,
               const CellOrigin& origin);

  int dimension_ = 3;
  std::size_t numPatches_ = 0;
  bool hasVolumeCells_ = false;
  std::vector<std::int64_t> patchFirst_;  // numPatches_ + 1 entries
  std::vector<std::array<int, 3>> splineSpans_;  // per patch: its span grid (zeros unless a B-spline patch)
  std::vector<kernels::CellShape> shapes_;
  std::vector<std::int64_t> pointOffset_;   // first coordinate of each cell in points_
  std::vector<std::int64_t> weightOffset_;  // first weight of each cell in weights_, -1 if polynomial
  std::vector<double> points_;
  std::vector<double> weights_;
  std::vector<CellOrigin> origins_;
  std::vector<kernels::CellSolver> solvers_;  // built last: they point into points_ and weights_
  std::vector<AffineRegion> regions_;
  std::vector<std::int32_t> regionOfCell_;    // -1 outside every region
  std::vector<std::int64_t> subdivisions_;    // cell index, or -1 - region index
  TetAdjacency tetAdjacency_;
};

/// Converts the public cell type to the kernels' one.
kernels::CellType ToKernelType(CellType type);

/// Vertices per linear mesh cell, and the finite-element to Bezier order
/// (docs/formats.md: quads and hexes list their faces counter-clockwise,
/// Bezier nets are tensor products with the first coordinate fastest):
/// control point k of the degree-1 cell is vertex bezierFromFe[k].
struct MeshCellLayout {
  int vertices;
  int bezierFromFe[8];
};
MeshCellLayout LayoutOf(CellType type);

}  // namespace invmap::engine
