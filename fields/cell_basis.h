// The basis a Bezier cell interpolates with: its Bernstein polynomials (or
// their rational quotients) at reference coordinates, in control point order.
#pragma once

#include <vector>

#include "kernels/cell_shape.h"

namespace invmap::fields {

/// Values of every basis function of a cell of `shape` at reference
/// coordinates `params` (shape.paramDim() values, docs/formats.md section 1),
/// in control point order (tensor products: first factor fastest), written to
/// `out` (resized to shape.numControlPoints()). With `weights` (one per
/// control point) the rational basis w_k B_k / sum_j w_j B_j. The values sum
/// to 1, so a field's coefficients combined with them give its value there.
void EvaluateCellBasis(const kernels::CellShape& shape, const double* params, const double* weights,
                       std::vector<double>* out);

}  // namespace invmap::fields
