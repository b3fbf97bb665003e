// A whole cell excluded from one evaluation of its map: the tangent plane of
// the squared distance, which bounds it from below wherever it is convex.
#pragma once

#include "kernels/cell_map.h"

namespace invmap::kernels {

/// The least value over the reference domain (a product of simplices) of the
/// tangent plane at `ref` of g = W^2 (f - level), f = |x - point|^2, divided
/// by W(ref)^2 > 0, minus a bound on its rounding. `jet`: the map at `ref`
/// to at least first order; `size`: the cell's length scale.
///
/// A positive value proves g > 0, so f > level, over the whole cell when g
/// is convex over the whole cell (whose domain is convex and holds ref):
/// when the net of q - level WW (= g in Bernstein form) passes
/// HessianStencil::IsConvex, or CurvatureBounds proves it. Near the
/// closest point of a neighbouring cell that is plainly farther than the
/// best, the plane is nearly flat along the cell and rises into it, so the
/// cell is excluded without converging a local solve on it.
double TangentPlaneLowerBound(const CellShape& shape, int ambientDim, const MapJet& jet, const double* point,
                              const double* ref, double level, double size);

}  // namespace invmap::kernels
