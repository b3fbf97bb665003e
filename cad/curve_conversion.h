// A model's curves as exact B-splines where that is possible: edges in space
// and their pcurves in a face's parameters, over an edge's parameter range.
#pragma once

#include <Geom2d_Curve.hxx>
#include <Geom_Curve.hxx>

#include "cad/spline_builders.h"
#include "invmap/invmap.h"

namespace invmap::cad {

/// A converted curve; `approximated` when it is not exact (offset curves,
/// hyperbolas in space, degrees above invmap's 8 in space and 25 in the
/// plane), then `deviation` from it (measured; within `tolerance` unless
/// refining gave up).
struct ConvertedCurve {
  SplineCurve curve;
  bool approximated = false;
  double deviation = 0.0;
};

/// `curve` over [first, last] (first < last), its parameter kept: lines and
/// B-splines by their knots, circles and ellipses as angular arcs.
/// Circles and ellipses in spans of at most `arcSpan` (spline_builders.h).
ConvertedCurve ConvertCurve(const Handle(Geom_Curve)& curve, double first, double last, double tolerance,
                            double arcSpan = kArcSpan);
ConvertedCurve ConvertCurve2d(const Handle(Geom2d_Curve)& curve, double first, double last, double tolerance);

}  // namespace invmap::cad
