// The cells of a manifold: every patch turned into Bezier cells, with their
// solvers (bounds, precomputed distance nets), the way back to the patch,
// the affine regions and the volume cells' face neighbours. A geometry of
// triangle meshes alone keeps only their vertices and corners
// (engine/mesh_triangles.h).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "common/check.h"
#include "engine/affine_regions.h"
#include "engine/bezier_nets.h"
#include "engine/face_adjacency.h"
#include "engine/mesh_triangles.h"
#include "invmap/invmap.h"
#include "kernels/analytic_surface.h"
#include "kernels/cell_solver.h"

namespace invmap::engine {

/// All cells of a geometry. Immutable; safe to read from many threads.
/// Movable, not copyable (the solvers point into the nets' arrays).
///
/// A geometry made only of linear triangle meshes in 3D (MeshTriangles::
/// Applies) keeps no per-cell object: its cells are answered in closed form
/// from their vertices (shape, box, size, vertices and origin below read
/// them). solver() of such a cell builds its solver on first use and keeps
/// it: the batch search never asks for one (it solves the triangles from
/// SimplexItems), the rarer paths that do (local minima, trackers, model
/// distances) pay for the cells they touch.
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
  /// The cells of a geometry of triangle meshes alone (what Build makes
  /// of one), from its triangles already taken (MeshTriangles::Take).
  explicit CellStore(MeshTriangles triangles);

  CellStore(CellStore&&) noexcept;
  CellStore& operator=(CellStore&&) noexcept;
  CellStore(const CellStore&) = delete;
  CellStore& operator=(const CellStore&) = delete;
  ~CellStore();

  int dimension() const { return nets_.dimension; }
  std::int64_t size() const { return size_; }
  const kernels::CellSolver& solver(std::int64_t cell) const {
    INVMAP_ASSERT(cell >= 0 && cell < size(), "cell " << cell << " not in [0, " << size() << ")");
    return triangles_.empty() ? solvers_[cell] : TriangleSolver(cell);
  }
  /// Where `cell` came from. Mesh triangles keep no origin: theirs is made
  /// on the call, in a slot of this thread that the eighth call after it
  /// reuses (the engine copies it at once).
  const CellOrigin& origin(std::int64_t cell) const {
    INVMAP_ASSERT(cell >= 0 && cell < size(), "cell " << cell << " not in [0, " << size() << ")");
    return triangles_.empty() ? nets_.origins[cell] : TriangleOrigin(cell);
  }
  /// The shape of `cell` (its type and degrees), solver(cell).cell().shape.
  const kernels::CellShape& shape(std::int64_t cell) const {
    return triangles_.empty() ? nets_.shapes[cell] : triangleShape_;
  }
  /// The diagonal of `cell`'s control-point box, solver(cell).size().
  double cellSize(std::int64_t cell) const;
  /// True when `cell` is a volume (paramDim == dimension), solver(cell).isFullRank().
  bool isFullRank(std::int64_t cell) const { return shape(cell).paramDim() == dimension(); }
  /// True when `cell` is an affine segment, triangle or tetrahedron (solved
  /// in closed form), solver(cell).isAffineSimplex().
  bool isAffineSimplex(std::int64_t cell) const {
    return !triangles_.empty() || solvers_[cell].isAffineSimplex();
  }
  /// `cell` as the kernels read it, solver(cell).cell(); a mesh triangle's
  /// vertices are copied to `triangle` (9 values), which the view points to.
  kernels::CellView View(std::int64_t cell, double* triangle) const;
  /// The mesh triangles of a geometry of them alone; empty otherwise.
  const MeshTriangles& meshTriangles() const { return triangles_; }
  /// Affine simplices: vertex `v` of `cell`, solver(cell).CornerPoint(v).
  const double* SimplexVertex(std::int64_t cell, int v) const {
    return triangles_.empty() ? solvers_[cell].CornerPoint(v) : triangles_.Vertex(cell, v);
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
  /// The closed-form description of `cell` when it lies on a face's
  /// elementary surface (Patch::analytic, kernels/analytic_surface.h): the
  /// search answers it with SolveAnalyticCell instead of solver(cell).
  /// Null otherwise.
  const kernels::AnalyticCell* analytic(std::int64_t cell) const {
    if (analyticOf_.empty()) return nullptr;
    const std::int32_t a = analyticOf_[cell];
    return a < 0 ? nullptr : &nets_.trimmed.analyticCells[a].second;
  }
  /// True when some patch is a TrimmedSurface (a CAD face): features that
  /// enumerate a cell's minima without its trimming region refuse it.
  bool hasTrimmedSurfaces() const { return !nets_.trimmed.empty(); }

  /// Affine regions of the B-spline patches (engine/affine_regions.h).
  const std::vector<AffineRegion>& regions() const { return regions_; }
  /// Subdivisions (algorithm 6): what the BVH holds and the search visits:
  /// every affine region once, and every cell outside a region.
  /// Without regions the subdivisions are the cells, in order.
  std::int64_t numSubdivisions() const {
    return regions_.empty() ? size() : static_cast<std::int64_t>(subdivisions_.size());
  }
  /// True when subdivision `s` is an affine region.
  bool isRegion(std::int64_t s) const { return !regions_.empty() && subdivisions_[s] < 0; }
  /// The cell of a subdivision that is a cell.
  std::int64_t subdivisionCell(std::int64_t s) const { return regions_.empty() ? s : subdivisions_[s]; }
  /// The region of a subdivision that is a region.
  const AffineRegion& subdivisionRegion(std::int64_t s) const { return regions_[-1 - subdivisions_[s]]; }
  /// The cell of subdivision `s` when it is an affine segment, triangle or
  /// tetrahedron (solved in closed form), else -1.
  std::int64_t affineSimplexCell(std::int64_t s) const {
    return !isRegion(s) && isAffineSimplex(subdivisionCell(s)) ? subdivisionCell(s) : -1;
  }
  /// True when `cell` belongs to an affine region (it is then searched only
  /// as part of its region).
  bool inRegion(std::int64_t cell) const { return !regions_.empty() && regionOfCell_[cell] >= 0; }
  /// The cell of the same B-spline patch `step[d]` spans (-1, 0 or +1)
  /// away from `cell` along each of its parameter directions d, or -1 when
  /// that leaves the patch, lands on a trimmed surface's span outside its
  /// region, or `cell` is not a B-spline patch's or a trimmed surface's.
  std::int64_t SplineNeighbor(std::int64_t cell, const int* step) const;
  /// Face neighbours of the volume cells (empty without volume cells).
  const FaceAdjacency& faceAdjacency() const { return faceAdjacency_; }
  /// Bounds of a subdivision's cells (from its solver, which a mesh
  /// triangle builds: SubdivisionBox does not).
  const double* subdivisionBoxLo(std::int64_t s) const {
    return isRegion(s) ? subdivisionRegion(s).boxLo : solver(subdivisionCell(s)).boxLo();
  }
  const double* subdivisionBoxHi(std::int64_t s) const {
    return isRegion(s) ? subdivisionRegion(s).boxHi : solver(subdivisionCell(s)).boxHi();
  }
  /// The box of subdivision `s`, subdivisionBoxLo and Hi, in lo[0..2] and
  /// hi[0..2] (0 past the dimension).
  void SubdivisionBox(std::int64_t s, double* lo, double* hi) const;
  /// Appends to `xyz` (3 coordinates per point, 0 as the third in 2D) points
  /// whose convex hull holds subdivision `s`: a cell's control points
  /// (weights are positive), a region's parameter-box corners mapped by its
  /// affine map. Nothing for volumes: an oriented box (engine/oriented_box.h)
  /// around a solid prunes little that its axis-aligned box does not.
  void SubdivisionHullPoints(std::int64_t s, std::vector<double>* xyz) const;

 private:
  /// The solvers of mesh triangles built so far (defined in cell_store.cpp).
  struct TriangleSolvers;

  CellStore(BezierNets nets, std::vector<kernels::CellSolver> solvers, FaceAdjacency faceAdjacency,
            std::vector<AffineRegion> regions);

  /// Sets largestSize_ from the cells' boxes.
  void FindLargestSize();
  const kernels::CellSolver& TriangleSolver(std::int64_t cell) const;
  const CellOrigin& TriangleOrigin(std::int64_t cell) const;

  BezierNets nets_;
  std::int64_t size_ = 0;
  std::vector<kernels::CellSolver> solvers_;  // they point into nets_.points and nets_.weights
  std::vector<AffineRegion> regions_;
  // Both empty without regions (the subdivisions are then the cells).
  std::vector<std::int32_t> regionOfCell_;    // -1 outside every region
  std::vector<std::int64_t> subdivisions_;    // cell index, or -1 - region index
  FaceAdjacency faceAdjacency_;
  double largestSize_ = 0.0;
  // Per cell: its entry in nets_.trimmed.analyticCells, or -1 (empty when
  // no cell has one).
  std::vector<std::int32_t> analyticOf_;
  // Geometries of triangle meshes alone: their cells (empty otherwise), and
  // the solvers solver() built for them.
  MeshTriangles triangles_;
  kernels::CellShape triangleShape_;
  std::unique_ptr<TriangleSolvers> triangleSolvers_;
};

}  // namespace invmap::engine
