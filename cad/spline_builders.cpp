#include "cad/spline_builders.h"

#include <algorithm>
#include <cmath>

namespace invmap::cad {

SplineCurve LineCurve(int dim, const double* p0, const double* p1, double t0, double t1) {
  SplineCurve line;
  line.degree = 1;
  line.knots = {t0, t0, t1, t1};
  line.points.assign(p0, p0 + dim);
  line.points.insert(line.points.end(), p1, p1 + dim);
  return line;
}

SplineCurve ArcCurve(int dim, const double* center, const double* x, const double* y, double a, double b) {
  // At most a twelfth of a turn per span: the weights then differ by at most
  // 3.5 % (cos 15 degrees), within the 5 % where the cell search's curvature
  // bounds hold for rational cells (kernels/curvature_bounds.h), and the
  // arc's parameter stays close to its angle.
  const int spans = std::max(1, static_cast<int>(std::ceil((b - a) / (M_PI / 6.0) - 1e-9)));
  SplineCurve arc;
  arc.degree = 2;
  arc.angular = true;
  const double step = (b - a) / spans;
  const double h = 0.5 * step;
  auto at = [&](double t, double scale) {
    for (int k = 0; k < dim; ++k) arc.points.push_back(center[k] + scale * (std::cos(t) * x[k] + std::sin(t) * y[k]));
  };
  arc.knots = {a, a, a};
  at(a, 1.0);
  arc.weights.push_back(1.0);
  for (int s = 0; s < spans; ++s) {
    const double lo = a + s * step;
    const double hi = s + 1 == spans ? b : a + (s + 1) * step;
    // The middle control point: where the end tangents meet.
    at(lo + h, 1.0 / std::cos(h));
    arc.weights.push_back(std::cos(h));
    at(hi, 1.0);
    arc.weights.push_back(1.0);
    arc.knots.push_back(hi);
    arc.knots.push_back(hi);
  }
  arc.knots.push_back(b);
  return arc;
}

SplineCurve Reversed(const SplineCurve& curve) {
  SplineCurve reversed = curve;
  const int dim = static_cast<int>(curve.points.size() / (curve.knots.size() - curve.degree - 1));
  const std::size_t n = curve.points.size() / dim;
  for (std::size_t i = 0; i < n; ++i) {
    std::copy_n(&curve.points[(n - 1 - i) * dim], dim, &reversed.points[i * dim]);
  }
  std::reverse(reversed.weights.begin(), reversed.weights.end());
  for (std::size_t i = 0; i < curve.knots.size(); ++i) reversed.knots[i] = -curve.knots[curve.knots.size() - 1 - i];
  return reversed;
}

SurfaceSpline Revolve(const SplineCurve& profile, const double* origin, const double* x, const double* y,
                      const double* z, double a, double b) {
  // Each control point of the profile turns on a circle about the axis; the
  // circle's arc, scaled by the point's weight, is a row of the net.
  const double unit[3] = {0, 0, 0};
  const SplineCurve shape = ArcCurve(3, unit, x, y, a, b);  // angles and weights of one row
  SurfaceSpline surface;
  surface.degrees[0] = 2;
  surface.degrees[1] = profile.degree;
  surface.knots[0] = shape.knots;
  surface.knots[1] = profile.knots;
  surface.angular[0] = true;
  surface.angular[1] = profile.angular;
  const int nu = static_cast<int>(shape.weights.size());
  const int nv = static_cast<int>(profile.points.size() / 3);
  surface.counts[0] = nu;
  surface.counts[1] = nv;
  for (int j = 0; j < nv; ++j) {
    const double* p = &profile.points[3 * j];
    double local[3];
    for (int k = 0; k < 3; ++k) local[k] = p[k] - origin[k];
    const double px = local[0] * x[0] + local[1] * x[1] + local[2] * x[2];
    const double py = local[0] * y[0] + local[1] * y[1] + local[2] * y[2];
    const double pz = local[0] * z[0] + local[1] * z[1] + local[2] * z[2];
    double center[3], r0[3], r90[3];
    for (int k = 0; k < 3; ++k) {
      center[k] = origin[k] + pz * z[k];
      r0[k] = px * x[k] + py * y[k];
      r90[k] = -py * x[k] + px * y[k];
    }
    const SplineCurve row = ArcCurve(3, center, r0, r90, a, b);
    surface.points.insert(surface.points.end(), row.points.begin(), row.points.end());
    const double w = profile.weights.empty() ? 1.0 : profile.weights[j];
    for (int i = 0; i < nu; ++i) surface.weights.push_back(w * row.weights[i]);
  }
  return surface;
}

SurfaceSpline Extrude(const SplineCurve& profile, const double* d, double v0, double v1) {
  SurfaceSpline surface;
  surface.degrees[0] = profile.degree;
  surface.degrees[1] = 1;
  surface.knots[0] = profile.knots;
  surface.knots[1] = {v0, v0, v1, v1};
  surface.angular[0] = profile.angular;
  const int nu = static_cast<int>(profile.points.size() / 3);
  surface.counts[0] = nu;
  surface.counts[1] = 2;
  for (const double v : {v0, v1}) {
    for (int i = 0; i < nu; ++i) {
      for (int k = 0; k < 3; ++k) surface.points.push_back(profile.points[3 * i + k] + v * d[k]);
    }
    surface.weights.insert(surface.weights.end(), profile.weights.begin(), profile.weights.end());
  }
  return surface;
}

SurfaceSpline PlanePatch(const double* origin, const double* x, const double* y, double u0, double u1, double v0,
                         double v1) {
  SurfaceSpline surface;
  surface.knots[0] = {u0, u0, u1, u1};
  surface.knots[1] = {v0, v0, v1, v1};
  surface.counts[0] = surface.counts[1] = 2;
  for (const double v : {v0, v1}) {
    for (const double u : {u0, u1}) {
      for (int k = 0; k < 3; ++k) surface.points.push_back(origin[k] + u * x[k] + v * y[k]);
    }
  }
  return surface;
}

void SetSurface(const SurfaceSpline& surface, Patch* patch) {
  patch->kind = Patch::Kind::TrimmedSurface;
  patch->degrees = {surface.degrees[0], surface.degrees[1]};
  patch->knots = {surface.knots[0], surface.knots[1]};
  patch->counts = {surface.counts[0], surface.counts[1]};
  patch->points = surface.points;
  patch->weights = surface.weights;
  patch->angular = {static_cast<std::uint8_t>(surface.angular[0]), static_cast<std::uint8_t>(surface.angular[1])};
}

}  // namespace invmap::cad
