// The cells of a manifold: every patch turned into Bezier cells, with their
// solvers (bounds, precomputed distance nets), the way back to the patch,
// the affine regions and the volume cells' face neighbours.
#pragma once

#include <cstdint>
#include <vector>

#include "common/check.h"
#include "engine/affine_regions.h"
#include "engine/bezier_nets.h"
#include "engine/face_adjacency.h"
#include "invmap/invmap.h"
#include "kernels/cell_solver.h"

namespace invmap::engine {

/// All cells of a geometry. Immutable; safe to read from many threads.
/// Movable, not copyable (the solvers point into the nets' arrays).
class CellStore {
 public:
  /// Builds the cells of `geometry`, in steps that each take the finished
  /// results of the ones before: the Bezier nets (ToBezierNets), their
  /// solvers (bounds and distance nets, in parallel; those of cells a
  /// trimming loop crosses search within its region), the volume cells' face
  /// neighbours, the affine regions, and the subdivisions. Precondition:
  /// ValidateGeometry(geometry) found no problem (engine/geometry_validation.h).
  /// `maxThreads` bounds the threads used (0 = all).
  static CellStore Build(const Geometry& geometry, int maxThreads);

  CellStore(CellStore&&) = default;
  CellStore& operator=(CellStore&&) = default;
  CellStore(const CellStore&) = delete;
  CellStore& operator=(const CellStore&) = delete;

  int dimension() const { return nets_.dimension; }
  std::int64_t size() const { return static_cast<std::int64_t>(solvers_.size()); }
  const kernels::CellSolver& solver(std::int64_t cell) const {
    INVMAP_ASSERT(cell >= 0 && cell < size(), "cell " << cell << " not in [0, " << size() << ")");
    return solvers_[cell];
  }
  const CellOrigin& origin(std::int64_t cell) const {
    INVMAP_ASSERT(cell >= 0 && cell < size(), "cell " << cell << " not in [0, " << size() << ")");
    return nets_.origins[cell];
  }
  std::size_t numPatches() const { return nets_.numPatches; }
  /// True when some cell is a volume (paramDim == dimension), whose exact
  /// inside hits the search tries first.
  bool hasVolumeCells() const { return nets_.hasVolumeCells; }
  /// Index of the first cell of `patch` (cells of a patch are contiguous);
  /// patchFirstCell(numPatches()) == size().
  std::int64_t patchFirstCell(std::size_t patch) const { return nets_.patchFirst[patch]; }
  /// The largest size of a cell or affine region, or more (the diagonal of
  /// all cells' boxes): its gap band (PointSearch::GapBand) is at least any
  /// subdivision's, so a box test widened by it never loses a cell whose
  /// answer would be found within the gap tolerance.
  double largestSize() const { return largestSize_; }
  /// Heap memory of the cells: control points, weights, solvers and their nets.
  std::size_t MemoryBytes() const;

  /// The parameters reported for reference point `ref` of `cell` (3 values,
  /// NaN where unused): knot values, angles where a direction is angular,
  /// and for an edge of a trimmed surface its pcurve's (u, v).
  void ReportedParameters(std::int64_t cell, const double* ref, double* params) const;
  /// True when some patch is a TrimmedSurface (a CAD face): features that
  /// enumerate a cell's minima without its trimming region refuse it.
  bool hasTrimmedSurfaces() const { return !nets_.trimmed.empty(); }

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
  /// that leaves the patch, lands on a trimmed surface's span outside its
  /// region, or `cell` is not a B-spline patch's or a trimmed surface's.
  std::int64_t SplineNeighbor(std::int64_t cell, const int* step) const;
  /// Face neighbours of the volume cells (empty without volume cells).
  const FaceAdjacency& faceAdjacency() const { return faceAdjacency_; }
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
  CellStore(BezierNets nets, std::vector<kernels::CellSolver> solvers, FaceAdjacency faceAdjacency,
            std::vector<AffineRegion> regions);

  BezierNets nets_;
  std::vector<kernels::CellSolver> solvers_;  // they point into nets_.points and nets_.weights
  std::vector<AffineRegion> regions_;
  std::vector<std::int32_t> regionOfCell_;    // -1 outside every region
  std::vector<std::int64_t> subdivisions_;    // cell index, or -1 - region index
  FaceAdjacency faceAdjacency_;
  double largestSize_ = 0.0;
};

}  // namespace invmap::engine
