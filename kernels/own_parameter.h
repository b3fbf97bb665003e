// A surface's or curve's own parameter from a Bezier cell's reference
// coordinate. B-spline cells report knot values, lo + scale * w. Circular
// directions (the angle of a cylinder, a cone, a sphere, a torus, a
// revolution; the eccentric angle of an ellipse) are exact only as rational
// quadratics, whose parameter is not the angle: each knot span [lo, lo +
// scale] there is one symmetric arc (weights 1, cos(scale / 2), 1) and its
// knot values are the angles at its ends, so the angle inside it follows
// from the half-angle tangent, which such an arc's parameter moves linearly.
#pragma once

#include <cmath>

namespace invmap::kernels {

/// The own parameter at reference coordinate w in [0, 1] of a span [lo, lo +
/// scale]: linear, or (angular) the angle of a symmetric rational quadratic
/// arc: lo + h + 2 atan(tan(h / 2) (2 w - 1)) with h = scale / 2. Monotone
/// increasing in w either way, exact at both ends.
inline double OwnParameter(double lo, double scale, bool angular, double w) {
  if (!angular) return lo + scale * w;
  if (w <= 0.0) return lo;
  if (w >= 1.0) return lo + scale;
  const double h = 0.5 * scale;
  return lo + h + 2.0 * std::atan(std::tan(0.5 * h) * (2.0 * w - 1.0));
}

/// The inverse of OwnParameter: the reference coordinate of own parameter
/// `own` in the span (clamped to [0, 1]).
inline double ReferenceOfOwn(double lo, double scale, bool angular, double own) {
  double w;
  if (!angular) {
    w = (own - lo) / scale;
  } else {
    const double h = 0.5 * scale;
    w = 0.5 * (1.0 + std::tan(0.5 * (own - lo - h)) / std::tan(0.5 * h));
  }
  return w < 0.0 ? 0.0 : w > 1.0 ? 1.0 : w;
}

}  // namespace invmap::kernels
