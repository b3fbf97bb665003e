// The basis a Bezier cell interpolates with: its Bernstein polynomials (or
// their rational quotients) at reference coordinates, in control point order.
#pragma once

#include "kernels/cell_shape.h"

namespace invmap::fields {

/// The most control points a cell has: a hexahedron of the highest degree.
constexpr int kMaxCellBasis = (kernels::kMaxDegree + 1) * (kernels::kMaxDegree + 1) * (kernels::kMaxDegree + 1);

/// Writes the values of every basis function of a cell of `shape` at
/// reference coordinates `params` (shape.paramDim() values, docs/formats.md
/// section 1) to out[0 .. shape.numControlPoints()), in control point order
/// (tensor products: first factor fastest); `out` holds kMaxCellBasis
/// values. With `weights` (one per control point), the rational basis
/// w_k B_k / sum_j w_j B_j. The values sum to 1, so a field's coefficients
/// combined with them give its value there. Returns the number of values.
int EvaluateCellBasis(const kernels::CellShape& shape, const double* params, const double* weights, double* out);

}  // namespace invmap::fields
