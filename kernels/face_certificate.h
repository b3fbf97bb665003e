// A certificate that a closest point on the boundary of a cell's domain is
// the minimum over a whole subdomain: the squared distance grows away from
// the face it lies on. Covers what the convexity certificate cannot: points
// beyond a patch's boundary and feet of perpendiculars in a neighbouring cell,
// where the distance is not convex but is monotone across the subdomain.
#pragma once

#include "kernels/bernstein_net.h"
#include "kernels/cell_shape.h"

namespace invmap::kernels {

/// True for the shapes IsMinimalOnFace accepts: tensor products of lines
/// (line, quad, hex cells).
bool HasFaceCertificate(const CellShape& shape);

/// `f` is the net of q - f* WW on a subdomain (local coordinates t in
/// [0, 1]^d) that holds the KKT point x*. side[d] is 0 or 1 when x* lies on
/// the subdomain's face t_d = side[d] and that face is part of the cell's
/// boundary, -1 when direction d is free. Returns true when f >= 0 is proved
/// on the whole subdomain: every derivative net along a constrained direction
/// has the sign that makes f grow away from its face (so f is at least its
/// value on the face F where they meet), and f restricted to F is convex
/// (so, x* being stationary in F's free directions, f >= f(x*) = 0 on F); a
/// vertex F needs nothing more. False when nothing is constrained. Every
/// sign is proved beyond the rounding `noise` of f's coefficients.
bool IsMinimalOnFace(const CellShape& shape, const double* f, const NetNoise& noise, const int* side);

}  // namespace invmap::kernels
