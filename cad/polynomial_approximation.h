// Approximation of what cannot be written exactly as invmap cells (surfaces
// and curves of degree above 8, offsets of free-form surfaces, sweeps,
// hyperbolas): piecewise polynomials of degree 8 that interpolate the exact
// geometry at Chebyshev-Lobatto nodes of each piece, in the geometry's own
// parameters (so reported parameters stay its own). Pieces start at the
// geometry's own breaks of continuity and are halved until the deviation,
// measured at points between the nodes, is within the tolerance; the
// deviation reached is reported, whatever it is.
#pragma once

#include <Adaptor2d_Curve2d.hxx>
#include <Adaptor3d_Curve.hxx>
#include <Adaptor3d_Surface.hxx>

#include "cad/spline_builders.h"

namespace invmap::cad {

/// `surface` over its own bounds. `*deviation` receives the largest
/// distance measured between the approximation and the surface.
SurfaceSpline ApproximateSurface(const Adaptor3d_Surface& surface, double tolerance, double* deviation);

/// `curve` (3D) over its own bounds.
SplineCurve ApproximateCurve(const Adaptor3d_Curve& curve, double tolerance, double* deviation);

/// `curve` (2D) over its own bounds.
SplineCurve ApproximateCurve2d(const Adaptor2d_Curve2d& curve, double tolerance, double* deviation);

}  // namespace invmap::cad
