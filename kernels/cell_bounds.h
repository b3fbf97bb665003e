// Bounds and classification of a cell from its control net.
#pragma once

#include "kernels/cell_map.h"

namespace invmap::kernels {

/// Axis-aligned box of the control points. By the convex hull property
/// (positive weights, Cartesian control points) it contains the whole cell.
/// Coordinates past ambientDim are set to 0.
void ComputeControlBox(const CellView& cell, double* lo, double* hi);

/// True when the cell's map is affine: polynomial (or all weights equal) and
/// every control point is the image of its lattice location (a / degree)
/// under one affine map, within `1e-12 * size`.
bool IsAffineCell(const CellView& cell, double size);

/// Centroid of the reference domain (docs/formats.md section 1).
void ReferenceCenter(const CellShape& shape, double* ref);

/// Reference location of control point `c` (its lattice point a / degree per factor).
void ControlPointLocation(const CellShape& shape, int c, double* ref);

}  // namespace invmap::kernels
