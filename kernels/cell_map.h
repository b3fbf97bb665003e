// A Bezier cell (polynomial or rational) and the evaluation of its map.
#pragma once

#include "kernels/bernstein.h"
#include "kernels/cell_shape.h"

namespace invmap::kernels {

/// Non-owning view of one Bezier cell: its shape, ambient dimension and
/// control net. The caller keeps the arrays alive while the view is used.
struct CellView {
  CellShape shape;
  int ambientDim = 3;  ///< 2 or 3; control points and query points have this many coordinates.
  /// Control points, Cartesian, numControlPoints() x ambientDim, point-major
  /// (point k's coordinate i at points[k * ambientDim + i]), docs/formats.md order.
  const double* points = nullptr;
  /// Optional: one positive weight per control point (rational cell); null
  /// for a polynomial cell.
  const double* weights = nullptr;
};

/// Value and derivatives of a cell's map x(u) at one reference point u.
/// Indices: k = ambient coordinate, i, j = parametric coordinate.
struct MapJet {
  double x[3] = {0, 0, 0};  ///< x_k(u).
  double d1[3][3] = {};     ///< dx_k/du_i.
  double d2[3][3][3] = {};  ///< d2x_k/du_i du_j (symmetric in i, j).
  /// (dW/du_i) / W (from order First), where W(u) is the weight function,
  /// the denominator of a rational map x = N / W: 0 for a polynomial cell.
  double logWeightSlope[3] = {0, 0, 0};
};

/// Evaluates the map of `cell` at reference coordinates `ref` (paramDim
/// values, docs/formats.md section 1) up to `order`. Outside the reference domain
/// the polynomial extension is evaluated. Rational cells use the quotient rule
/// on the homogeneous sums, so positive weights give a finite result.
void EvaluateMap(const CellView& cell, const double* ref, JetOrder order, MapJet* out);

}  // namespace invmap::kernels
