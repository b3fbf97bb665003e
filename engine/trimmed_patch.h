// Trimmed surfaces (Patch::Kind::TrimmedSurface): the cells of a face, the
// region of its parameter plane as kernels::TrimRegion pieces, and the way
// an answer on one of its edges is reported (the pcurve's (u, v) at the
// edge's parameter). AddTrimmedSurfaceCells turns such a patch into surface
// cells (those its loops cross carry a kernels::TrimmedCell, which their
// solvers search within) and edge curve cells. Validation is
// engine/geometry_validation.cpp's, like every patch's.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "invmap/invmap.h"
#include "kernels/analytic_surface.h"
#include "kernels/trim_region.h"
#include "kernels/trimmed_cell.h"

namespace invmap::engine {

struct BezierNets;

/// An edge's pcurve, ready to report (u, v) at an own parameter of the edge.
class EdgeParameters {
 public:
  EdgeParameters() = default;
  /// Precondition: `pcurve` is valid (2D) or has no points (then At gives NaN).
  explicit EdgeParameters(const SplineCurve& pcurve);

  /// The pcurve's (u, v) at own parameter `own` (clamped into its range).
  void At(double own, double* uv) const;
  std::size_t MemoryBytes() const;

 private:
  bool angular_ = false;
  int degree_ = 0;
  std::vector<double> spanLo_, spanHi_;  // knot range of each Bezier piece
  std::vector<double> points_;           // (degree_ + 1) * 2 per piece
  std::vector<double> weights_;          // (degree_ + 1) per piece, or empty
};

/// What the cells of a geometry's trimmed surfaces need beyond their nets.
/// The regions and trimmed cells are held by pointer: the solvers point at
/// them, and moving this keeps them in place.
struct TrimmedFaces {
  /// Each face's region of its parameter plane.
  std::vector<std::unique_ptr<kernels::TrimRegion>> regions;
  /// The cells the loops cross, with what their solvers search within.
  std::vector<std::pair<std::int64_t, std::unique_ptr<kernels::TrimmedCell>>> crossingCells;
  /// The edges' pcurves, indexed by CellOrigin::edge.
  std::vector<EdgeParameters> edges;
  /// Per patch: the cell of each span of its surface, -1 for spans wholly
  /// outside the region (empty for other kinds of patches).
  std::vector<std::vector<std::int64_t>> spanCells;
  /// The elementary surfaces of the faces whose Patch::analytic agrees with
  /// their B-spline surface (AnalyticSurfaceOf), and the cells on them,
  /// which the search answers in closed form (kernels/analytic_surface.h).
  std::vector<std::unique_ptr<kernels::AnalyticSurface>> analyticSurfaces;
  std::vector<std::pair<std::int64_t, kernels::AnalyticCell>> analyticCells;

  bool empty() const { return regions.empty(); }
  std::size_t MemoryBytes() const;
};

/// The elementary surface `patch.analytic` describes, in the form the
/// closed-form solves take, or null when there is none, it is one they do
/// not take (a torus that is not a ring), or it is not well formed (a
/// frame that is not orthonormal, a radius that is not positive and
/// finite). Whether it agrees with the B-spline surface is checked cell by
/// cell (AddTrimmedSurfaceCells).
std::unique_ptr<kernels::AnalyticSurface> AnalyticSurfaceOf(const Patch& patch);

/// Appends the cells of TrimmedSurface patch `p` to `nets` (and what they
/// need to nets->trimmed): the surface's knot spans, except those wholly
/// outside the region, then every edge's curve spans. When the patch's
/// analytic surface (AnalyticSurfaceOf) agrees with the surface at sample
/// points of every cell, within 1e-9 of the patch's size, its cells are
/// listed in nets->trimmed.analyticCells (but those the closed form does
/// not cover: kernels::ClosedFormCovers). Precondition:
/// ValidateGeometry found no problem.
void AddTrimmedSurfaceCells(const Patch& patch, std::size_t p, BezierNets* nets);

}  // namespace invmap::engine
