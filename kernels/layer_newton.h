// Newton in logarithmic coordinates for the thin layers of a rational cell
// whose weights lie orders of magnitude apart.
//
// Where a heavy weight's term is the product of two small coordinates (its
// control point on the edge between two vertices, next to a third), the map
// depends almost only on that product inside the layer: the squared
// distance has a valley along the hyperbola s * t = c, stiff across it by
// the weight ratio. Newton steps in (s, t) are straight lines that leave a
// curved valley at once, and the line search shortens them to nothing: the
// active-set solve stalls at its iteration cap, 1e-7 of the distance short
// of the minimum at weight ratios of 1e12. In v = log s the valley is the
// straight line v_s + v_t = log c, and Newton crosses it in a few steps.
#pragma once

#include "kernels/cell_map.h"

namespace invmap::kernels {

/// Coordinates below this (and above zero) are solved for in logarithms.
constexpr double kLayerCoordinate = 1e-3;

/// Minimizes |x(u) - point|^2 from `ref` (in place; a chart's reference
/// coordinates, kernels/cell_charts.h, so the small coordinates are the free
/// ones) by damped Newton steps in log u_i for every coordinate in (0,
/// kLayerCoordinate), in u_i for the others; coordinates at zero stay
/// there. Every accepted step decreases the distance and keeps `ref` in the
/// reference domain. Returns the iterations taken (0 when no coordinate is
/// in the layer). Not a KKT solve: the caller polishes with LocalSolve.
int LayerNewton(const CellView& cell, const double* point, double size, double* ref);

}  // namespace invmap::kernels
