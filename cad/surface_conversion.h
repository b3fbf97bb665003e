// A face's surface as an exact B-spline or NURBS surface over a box of its
// parameters, the knot values (and angles, in angular directions) being the
// surface's own parameters.
#pragma once

#include <Geom_Surface.hxx>

#include <string>

#include "cad/spline_builders.h"
#include "invmap/invmap.h"

namespace invmap::cad {

struct ConvertedSurface {
  SurfaceSpline surface;
  /// True when the surface could not be written exactly (offsets of
  /// free-form surfaces, sweeps, degrees above 8): then it deviates from it
  /// by `deviation` (measured; within `tolerance` unless refining gave up).
  bool approximated = false;
  double deviation = 0.0;
  /// The elementary surface it is (plane, cylinder, cone, sphere, torus, or
  /// an offset of one), for the closed-form solves (Patch::analytic);
  /// Kind::None for the others.
  AnalyticSurface analytic;
  /// The surface's kind, for `invmap info`: plane, cylinder, cone, sphere,
  /// torus, revolution, extrusion, bspline, bezier, offset or other.
  std::string type;
};

/// `surface` over [u0, u1] x [v0, v1] (u0 < u1, v0 < v1; angles within a
/// turn, a sphere's latitude within a half turn).
ConvertedSurface ConvertSurface(const Handle(Geom_Surface)& surface, double u0, double u1, double v0, double v1,
                                double tolerance);

}  // namespace invmap::cad
