// Bezier extraction: splits a B-spline or NURBS patch into one Bezier cell per
// non-empty knot span (docs/formats.md section 2, patch kind `bspline`).
#pragma once

#include <array>
#include <vector>

#include "kernels/cell_shape.h"

namespace invmap::engine {

/// A B-spline or NURBS curve (1 parametric direction), surface (2) or volume
/// (3), as read from a `bspline` patch of a geometry file. Directions are
/// u, v, w in that order. Its fields satisfy what ValidateGeometry
/// (engine/geometry_validation.h) asks of a `bspline` patch.
struct BSplinePatch {
  /// Ambient dimension, 2 or 3: the number of coordinates of every point.
  int ambientDim = 3;
  /// Polynomial degree per direction: [p], [p, q] or [p, q, r]; each in
  /// [1, kernels::kMaxDegree]. The number of entries is the parametric dimension.
  std::vector<int> degrees;
  /// One non-decreasing knot vector per direction; direction i has
  /// counts[i] + degrees[i] + 1 knots. Ends need not be clamped and interior
  /// knots may have any multiplicity.
  std::vector<std::vector<double>> knots;
  /// Number of control points per direction: n_u, (n_v, (n_w)); each at least
  /// degrees[i] + 1.
  std::vector<int> counts;
  /// n_u * n_v * n_w Cartesian points, u fastest then v then w, ambientDim
  /// values each: point (i, j, k) starts at ((k * n_v + j) * n_u + i) * ambientDim.
  std::vector<double> controlPoints;
  /// Optional: one positive weight per control point, same order. Empty means
  /// a polynomial (non-rational) patch.
  std::vector<double> weights;
};

/// The Bezier cells of one patch as flat buffers (struct of arrays). All
/// cells share one type and one set of degrees. Cell c covers the knot box
/// [spanLo, spanHi] (per direction) and maps reference coordinates s in [0, 1]
/// to patch parameters spanLo + (spanHi - spanLo) * s.
struct ExtractedCells {
  /// Line (curve), Quad (surface) or Hex (volume).
  kernels::CellType type = kernels::CellType::Line;
  /// Degree per factor, equal to the patch degrees; entries past paramDim are 0.
  std::array<int, kernels::kMaxFactors> degrees{};
  /// Coordinates per point, as in the patch.
  int ambientDim = 0;
  /// Parametric directions: 1, 2 or 3.
  int paramDim = 0;
  /// Number of cells: the non-empty knot spans inside the parameter domain,
  /// numbered u fastest, then v, then w.
  int numCells = 0;
  /// Non-empty spans per direction (1 past paramDim): numCells is their
  /// product, and cell (i, j, k) is i + spans[0] * (j + spans[1] * k).
  std::array<int, 3> spans{1, 1, 1};
  /// Control points per cell: the product of (degrees[i] + 1).
  int pointsPerCell = 0;
  /// numCells * pointsPerCell * ambientDim Cartesian coordinates; point k of
  /// cell c starts at (c * pointsPerCell + k) * ambientDim. Within a cell the
  /// points follow docs/formats.md tensor order (u fastest).
  std::vector<double> points;
  /// Optional: numCells * pointsPerCell positive weights in the order of
  /// `points`; empty exactly when the patch is polynomial.
  std::vector<double> weights;
  /// numCells * paramDim knot values: entry c * paramDim + d is the lower end
  /// of cell c's knot interval in direction d.
  std::vector<double> spanLo;
  /// numCells * paramDim knot values, upper ends, indexed as spanLo; always
  /// greater than the matching spanLo.
  std::vector<double> spanHi;
};

/// Converts `patch` into its Bezier cells by knot insertion (blossoming) on
/// every non-empty span of [t_p, t_n] in each direction; rational patches are
/// processed in homogeneous coordinates. The cells reproduce the patch
/// exactly up to rounding. Cost: O(cells * pointsPerCell * (max degree + 1))
/// time; besides the result, scratch for r + 1 w-layers of the net and, when
/// rational, a homogeneous copy of the net.
/// Precondition: the patch is valid (see BSplinePatch).
ExtractedCells ExtractBezierCells(const BSplinePatch& patch);

}  // namespace invmap::engine
