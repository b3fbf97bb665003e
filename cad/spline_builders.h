// Exact B-spline and NURBS forms of the curves and surfaces a CAD model is
// made of, built so that their knot values are the model's own parameters:
// lines and planes are linear in them, and circular directions are
// symmetric rational quadratic arcs whose knots are the angles at their
// ends (invmap's "angular" directions, kernels/own_parameter.h).
#pragma once

#include <cmath>
#include <vector>

#include "invmap/invmap.h"

namespace invmap::cad {

/// A B-spline or NURBS surface in the fields of a TrimmedSurface patch.
struct SurfaceSpline {
  int degrees[2] = {1, 1};
  std::vector<double> knots[2];
  int counts[2] = {0, 0};
  std::vector<double> points;   // 3 per control point, u fastest
  std::vector<double> weights;  // empty when polynomial
  bool angular[2] = {false, false};
};

/// The segment from p0 (parameter t0) to p1 (t1 > t0), `dim` coordinates.
SplineCurve LineCurve(int dim, const double* p0, const double* p1, double t0, double t1);

/// Longest span of an arc: a twelfth of a turn, whose weights differ by at
/// most 3.5 % (cos 15 degrees), within the 5 % where the cell search's
/// curvature bounds are kept for rational cells (kernels/cell_solver.cpp).
constexpr double kArcSpan = M_PI / 6.0;
/// Longest span of the arcs of a surface curved both ways (torus, sphere,
/// the revolution of an arc), whose weights are products of two arcs':
/// cos(10 degrees)^2 keeps them within 3.1 % too.
constexpr double kDoublyCurvedArcSpan = M_PI / 9.0;

/// The arc center + cos(t) x + sin(t) y, t in [a, b] (b > a), as spans of at
/// most `maxSpan` (an ellipse when x and y differ in length).
SplineCurve ArcCurve(int dim, const double* center, const double* x, const double* y, double a, double b,
                     double maxSpan = kArcSpan);

/// The curve reversed: its parameter t becomes -t.
SplineCurve Reversed(const SplineCurve& curve);

/// The surface swept by `profile` (3D, its parameter becomes v) turned
/// about the axis through `origin` along the unit vector z by the angle u
/// in [a, b] (right-handed about z when y = z x x; the sense of y otherwise),
/// with x a unit vector normal to z: u is angular, in spans of kArcSpan, or
/// of kDoublyCurvedArcSpan when the profile is rational.
SurfaceSpline Revolve(const SplineCurve& profile, const double* origin, const double* x, const double* y,
                      const double* z, double a, double b);

/// The surface profile(u) + v d, v in [v0, v1].
SurfaceSpline Extrude(const SplineCurve& profile, const double* d, double v0, double v1);

/// The plane origin + u x + v y over [u0, u1] x [v0, v1].
SurfaceSpline PlanePatch(const double* origin, const double* x, const double* y, double u0, double u1, double v0,
                         double v1);

/// Cuts the spans of a linear direction (degree 1: a cylinder's or a cone's
/// axis, an extrusion's direction) across a curved one into equal pieces no
/// longer than the curved direction's longest span, by exact knot insertion
/// (the parameters stay the same). Long thin cells defeat the cell solver's
/// whole-cell convexity certificate (kernels/curvature_bounds.h), whose
/// interval bounds grow with the distance from the cell's centre: on the
/// screw of OpenCascade's samples it passed for 29 % of the points before,
/// 88 % after, and the scan ran 1.9 times as fast.
void BalanceSpans(SurfaceSpline* surface);

/// Writes `surface` into the surface fields of `patch` (kind TrimmedSurface).
void SetSurface(const SurfaceSpline& surface, Patch* patch);

}  // namespace invmap::cad
