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

SplineCurve ArcCurve(int dim, const double* center, const double* x, const double* y, double a, double b,
                     double maxSpan) {
  const int spans = std::max(1, static_cast<int>(std::ceil((b - a) / maxSpan - 1e-9)));
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
  const double maxSpan = profile.weights.empty() ? kArcSpan : kDoublyCurvedArcSpan;
  const SplineCurve shape = ArcCurve(3, unit, x, y, a, b, maxSpan);  // angles and weights of one row
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
    const SplineCurve row = ArcCurve(3, center, r0, r90, a, b, maxSpan);
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

namespace {

/// Control point (row i along direction d, column j across it) of `s`.
const double* ControlPoint(const SurfaceSpline& s, int d, int i, int j) {
  const int index = d == 0 ? j * s.counts[0] + i : i * s.counts[0] + j;
  return &s.points[3 * static_cast<std::size_t>(index)];
}

double Length(const double* a, const double* b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

}  // namespace

void BalanceSpans(SurfaceSpline* s) {
  for (int d = 0; d < 2; ++d) {
    const int e = 1 - d;
    if (s->degrees[d] != 1 || s->degrees[e] < 2) continue;
    // The longest control-polygon run of one span across (direction e).
    double across = 0.0;
    for (int i = 0; i < s->counts[d]; ++i) {
      double run = 0.0;
      for (int j = 1; j < s->counts[e]; ++j) {
        run += Length(ControlPoint(*s, d, i, j - 1), ControlPoint(*s, d, i, j));
        if (j % s->degrees[e] == 0) {
          across = std::max(across, run);
          run = 0.0;
        }
      }
      across = std::max(across, run);
    }
    if (!(across > 0.0)) continue;
    // New rows along d: each span cut into as many equal pieces as make it
    // no longer than the longest span across.
    const int n = s->counts[d], m = s->counts[e];
    const std::vector<double>& knots = s->knots[d];
    std::vector<double> newKnots{knots[0], knots[1]};
    std::vector<std::vector<double>> rows;  // homogeneous (w x, w y, w z, w) per column
    auto row = [&](int i) {
      std::vector<double> r(4 * static_cast<std::size_t>(m));
      for (int j = 0; j < m; ++j) {
        const double* p = ControlPoint(*s, d, i, j);
        const int index = d == 0 ? j * s->counts[0] + i : i * s->counts[0] + j;
        const double w = s->weights.empty() ? 1.0 : s->weights[index];
        for (int k = 0; k < 3; ++k) r[4 * j + k] = w * p[k];
        r[4 * j + 3] = w;
      }
      return r;
    };
    rows.push_back(row(0));
    for (int i = 1; i < n; ++i) {
      const std::vector<double> a = rows.back(), b = row(i);
      double along = 0.0;
      for (int j = 0; j < m; ++j) along = std::max(along, Length(ControlPoint(*s, d, i - 1, j), ControlPoint(*s, d, i, j)));
      const int pieces = std::min(64, std::max(1, static_cast<int>(std::ceil(along / across - 1e-9))));
      const double t0 = knots[i], t1 = knots[i + 1];
      for (int k = 1; k < pieces; ++k) {
        const double f = static_cast<double>(k) / pieces;
        std::vector<double> r(a.size());
        for (std::size_t c = 0; c < r.size(); ++c) r[c] = (1.0 - f) * a[c] + f * b[c];
        rows.push_back(std::move(r));
        newKnots.push_back(t0 + f * (t1 - t0));
      }
      rows.push_back(b);
      newKnots.push_back(t1);
    }
    newKnots.push_back(knots.back());
    if (static_cast<int>(rows.size()) == n) continue;
    // Back to Cartesian points and weights, u fastest.
    const int rowsAlong = static_cast<int>(rows.size());
    SurfaceSpline out = *s;
    out.knots[d] = newKnots;
    out.counts[d] = rowsAlong;
    out.points.assign(3 * static_cast<std::size_t>(rowsAlong) * m, 0.0);
    if (!s->weights.empty()) out.weights.assign(static_cast<std::size_t>(rowsAlong) * m, 1.0);
    for (int i = 0; i < rowsAlong; ++i) {
      for (int j = 0; j < m; ++j) {
        const int index = d == 0 ? j * rowsAlong + i : i * out.counts[0] + j;
        const double w = rows[i][4 * j + 3];
        for (int k = 0; k < 3; ++k) out.points[3 * static_cast<std::size_t>(index) + k] = rows[i][4 * j + k] / w;
        if (!out.weights.empty()) out.weights[index] = w;
      }
    }
    *s = std::move(out);
  }
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
