// Trimmed surfaces (Patch::Kind::TrimmedSurface): the region of a face's
// parameter plane as kernels::TrimRegion pieces, and the way an answer on
// one of its edges is reported (the pcurve's (u, v) at the edge's parameter).
// CellStore::AddTrimmedSurface (trimmed_patch.cpp) turns such a patch into
// surface cells (those its loops cross carry a kernels::TrimmedCell) and
// edge curve cells.
#pragma once

#include <string>
#include <vector>

#include "engine/bezier_extraction.h"
#include "invmap/invmap.h"
#include "kernels/trim_region.h"

namespace invmap::engine {

/// The B-spline fields of a BSpline or TrimmedSurface patch (degrees, knots,
/// counts, points, weights) in `dim` coordinates, for ValidateBSplinePatch
/// and ExtractBezierCells.
BSplinePatch SplineOf(const Patch& patch, int dim);

/// Checks a SplineCurve with `dim` coordinates per control point; the
/// message names `field` ("edges[3].curve: knots: ...").
std::string ValidateSplineCurve(const SplineCurve& curve, int dim, const std::string& field);

/// Appends the closed loops of `loops` to `region` (their curves' Bezier
/// pieces, with a straight segment across each gap between consecutive
/// curves) and finishes it. Precondition: every curve is valid (2D).
void BuildTrimRegion(const std::vector<std::vector<SplineCurve>>& loops, kernels::TrimRegion* region);

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

}  // namespace invmap::engine
