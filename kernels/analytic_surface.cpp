#include "kernels/analytic_surface.h"

#include <algorithm>
#include <cmath>

#include "kernels/own_parameter.h"

namespace invmap::kernels {
namespace {

constexpr double kTwoPi = 2.0 * M_PI;

/// Below this share of the point's distance from the origin, the point is
/// taken to be on the axis (or at a centre): its azimuth is rounding noise.
constexpr double kDegenerate = 1e-12;

/// x modulo a turn, in [0, 2 pi).
double TurnRemainder(double x) {
  const double r = std::fmod(x, kTwoPi);
  return r < 0.0 ? r + kTwoPi : r;
}

/// The angle of [a, b] nearest `theta` along the circle.
double NearestAngle(double theta, double a, double b) {
  const double t = a + TurnRemainder(theta - a);
  if (t <= b) return t;
  return t - b <= a + kTwoPi - t ? b : a;
}

/// A rounding's width at the scale of [a, b]: a stationary point computed
/// on a box's side must not be lost to both boxes that share it.
double Slack(double a, double b) { return 1e-12 * (1.0 + std::max(std::abs(a), std::abs(b))); }

/// `theta`, or the turn of it, in [a, b] (within its slack, then clamped).
bool AngleInBox(double theta, double a, double b, double* t) {
  const double slack = Slack(a, b);
  double r = a + TurnRemainder(theta - a);
  if (r > b + slack) {
    if (r - kTwoPi < a - slack) return false;
    r -= kTwoPi;
  }
  *t = std::clamp(r, a, b);
  return true;
}

/// `x` in [a, b] (within its slack, then clamped).
bool ValueInBox(double x, double a, double b, double* t) {
  const double slack = Slack(a, b);
  if (!(x >= a - slack && x <= b + slack)) return false;
  *t = std::clamp(x, a, b);
  return true;
}

/// The query point in the surface's frame.
struct Local {
  double x, y, z;  // along the frame's axes, from its origin
  double rho;      // distance from the axis
  double phi;      // azimuth
  double reach;    // distance from the origin
};

Local ToLocal(const AnalyticSurface& s, const double* p) {
  const double a[3] = {p[0] - s.origin[0], p[1] - s.origin[1], p[2] - s.origin[2]};
  Local l;
  l.x = a[0] * s.x[0] + a[1] * s.x[1] + a[2] * s.x[2];
  l.y = a[0] * s.y[0] + a[1] * s.y[1] + a[2] * s.y[2];
  l.z = a[0] * s.z[0] + a[1] * s.z[1] + a[2] * s.z[2];
  l.rho = std::hypot(l.x, l.y);
  l.phi = std::atan2(l.y, l.x);
  l.reach = std::hypot(l.rho, l.z);
  return l;
}

/// The cell's box of own parameters.
struct Box {
  double u0, u1, v0, v1;
};

Box BoxOf(const AnalyticCell& cell) {
  return {cell.paramLo[0], cell.paramLo[0] + cell.paramScale[0], cell.paramLo[1],
          cell.paramLo[1] + cell.paramScale[1]};
}

/// True when a cone's apex (radius 0) lies in [v0, v1] or within a
/// rounding of it: there the surface is singular.
bool ApexInBox(const AnalyticSurface& s, const Box& box) {
  const double r0 = s.radius + box.v0 * s.sinAngle, r1 = s.radius + box.v1 * s.sinAngle;
  const double scale = std::abs(s.radius) + (std::abs(box.v0) + std::abs(box.v1)) * std::abs(s.sinAngle);
  return r0 * r1 <= 0.0 || std::min(std::abs(r0), std::abs(r1)) <= 1e-9 * scale;
}

/// The sign of a torus's parallels' radius R + r cos v over [v0, v1]: +1
/// or -1 when it keeps it, away from 0 by more than a rounding (always +1
/// on a ring torus; on a spindle torus, r > R, -1 on the inner part of its
/// tube), 0 when the box reaches the axis.
int ParallelsSign(const AnalyticSurface& s, const Box& box) {
  const double toPi = box.v0 + TurnRemainder(M_PI - box.v0);  // the first odd multiple of pi from v0 on
  const double toZero = box.v0 + TurnRemainder(-box.v0);      // the first even one
  const double leastCos = toPi <= box.v1 ? -1.0 : std::min(std::cos(box.v0), std::cos(box.v1));
  const double mostCos = toZero <= box.v1 ? 1.0 : std::max(std::cos(box.v0), std::cos(box.v1));
  const double rounding = 1e-9 * (s.radius + s.minorRadius);
  if (s.radius + s.minorRadius * leastCos > rounding) return 1;
  if (s.radius + s.minorRadius * mostCos < -rounding) return -1;
  return 0;
}

/// True when a sphere's box keeps to the latitudes [-pi/2, pi/2] (within
/// a rounding): past them cos v < 0 and the nearest azimuth is no longer
/// the point's for every v.
bool WithinLatitudes(const Box& box) {
  const double slack = Slack(box.v0, box.v1);
  return box.v0 >= -0.5 * M_PI - slack && box.v1 <= 0.5 * M_PI + slack;
}

/// The minimum of the squared distance over the closed box (see the
/// header's comment). False on a cone's box that holds its apex, a
/// spindle torus's that reaches its axis, a sphere's past a pole.
bool BoxMinimum(const AnalyticSurface& s, const Box& box, const Local& l, double* own) {
  switch (s.kind) {
    case AnalyticSurface::Kind::Plane:
      own[0] = std::clamp(l.x, box.u0, box.u1);
      own[1] = std::clamp(l.y, box.v0, box.v1);
      return true;
    case AnalyticSurface::Kind::Cylinder:
      own[0] = NearestAngle(l.phi, box.u0, box.u1);
      own[1] = std::clamp(l.z, box.v0, box.v1);
      return true;
    case AnalyticSurface::Kind::Cone: {
      if (ApexInBox(s, box)) return false;
      // Past the apex the parallels' radius is negative: the nearest
      // azimuth is then the opposite one.
      const bool beyondApex = s.radius + 0.5 * (box.v0 + box.v1) * s.sinAngle < 0.0;
      own[0] = NearestAngle(beyondApex ? l.phi + M_PI : l.phi, box.u0, box.u1);
      const double along = l.rho * std::cos(own[0] - l.phi);  // the point in the meridian half-plane
      own[1] = std::clamp((along - s.radius) * s.sinAngle + l.z * s.cosAngle, box.v0, box.v1);
      return true;
    }
    case AnalyticSurface::Kind::Sphere: {
      if (!WithinLatitudes(box)) return false;
      own[0] = NearestAngle(l.phi, box.u0, box.u1);
      const double along = l.rho * std::cos(own[0] - l.phi);
      own[1] = NearestAngle(std::atan2(l.z, along), box.v0, box.v1);
      return true;
    }
    case AnalyticSurface::Kind::Torus: {
      const int sign = ParallelsSign(s, box);
      if (sign == 0) return false;
      // On a spindle torus's inner part the nearest azimuth is the opposite one.
      own[0] = NearestAngle(sign > 0 ? l.phi : l.phi + M_PI, box.u0, box.u1);
      const double along = l.rho * std::cos(own[0] - l.phi);
      own[1] = NearestAngle(std::atan2(l.z, along - s.radius), box.v0, box.v1);
      return true;
    }
  }
  return false;
}

/// Every stationary point of the squared distance on the surface within the
/// closed box, in own[0 .. count); -1 when they are not isolated (a point
/// on the axis, at a sphere's centre, on a torus's centre circle).
int StationaryPoints(const AnalyticSurface& s, const Box& box, const Local& l, double (*own)[2]) {
  int count = 0;
  const auto add = [&](double u, double v, bool vAngular) {
    double t[2];
    if (s.kind == AnalyticSurface::Kind::Plane ? !ValueInBox(u, box.u0, box.u1, &t[0])
                                               : !AngleInBox(u, box.u0, box.u1, &t[0])) {
      return;
    }
    if (vAngular ? !AngleInBox(v, box.v0, box.v1, &t[1]) : !ValueInBox(v, box.v0, box.v1, &t[1])) return;
    own[count][0] = t[0];
    own[count][1] = t[1];
    ++count;
  };
  if (s.kind == AnalyticSurface::Kind::Plane) {
    add(l.x, l.y, false);
    return count;
  }
  if (l.rho <= kDegenerate * (l.reach + s.radius)) return -1;
  for (const double side : {1.0, -1.0}) {  // the point's meridian half-plane, then the opposite one
    const double u = side > 0.0 ? l.phi : l.phi + M_PI;
    const double along = side * l.rho;
    switch (s.kind) {
      case AnalyticSurface::Kind::Plane:
        break;
      case AnalyticSurface::Kind::Cylinder:
        add(u, l.z, false);
        break;
      case AnalyticSurface::Kind::Cone:
        add(u, (along - s.radius) * s.sinAngle + l.z * s.cosAngle, false);
        break;
      case AnalyticSurface::Kind::Sphere:
        add(u, std::atan2(l.z, along), false);  // the point's direction and its opposite
        break;
      case AnalyticSurface::Kind::Torus: {
        const double a = along - s.radius;
        if (std::hypot(a, l.z) <= kDegenerate * (l.reach + s.radius)) return -1;
        const double psi = std::atan2(l.z, a);
        add(u, psi, true);
        add(u, psi + M_PI, true);
        break;
      }
    }
  }
  return count;
}

/// Writes the answer at own parameters `own`; false when it is beyond `bound2`.
bool Answer(const AnalyticCell& cell, const double* point, const double* own, double bound2, CellSolveResult* r) {
  cell.surface->Evaluate(own[0], own[1], r->closest);
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) d2 += (point[k] - r->closest[k]) * (point[k] - r->closest[k]);
  if (d2 > bound2) return false;
  bool inside = true;
  for (int d = 0; d < 2; ++d) {
    r->ref[d] = ReferenceOfOwn(cell.paramLo[d], cell.paramScale[d], cell.angular[d], own[d]);
    inside = inside && r->ref[d] > 0.0 && r->ref[d] < 1.0;
  }
  r->ref[2] = 0.0;
  r->distance = std::sqrt(d2);
  r->status = inside ? PointStatus::Converged : PointStatus::ProjectedToBoundary;
  r->iterations = 0;
  return true;
}

/// True when the cell's region admits `own` or, in a box wider than a
/// turn, another turn of its angles within the box (the same point of the
/// surface, which the region may hold at one turn only); `own` becomes the
/// admitted one.
bool AdmittedTurn(const AnalyticCell& cell, const Box& box, double* own) {
  using Kind = AnalyticSurface::Kind;
  const Kind kind = cell.surface->kind;
  const bool periodic[2] = {kind != Kind::Plane, kind == Kind::Torus};
  const double lo[2] = {box.u0, box.v0}, hi[2] = {box.u1, box.v1};
  // Each angle's first turn in the box (within its slack), then every turn after it.
  double first[2];
  for (int d = 0; d < 2; ++d) {
    first[d] = own[d];
    if (periodic[d]) {
      while (first[d] - kTwoPi >= lo[d] - Slack(lo[d], hi[d])) first[d] -= kTwoPi;
    }
  }
  for (double u = first[0]; u <= hi[0] + Slack(lo[0], hi[0]); u += kTwoPi) {
    for (double v = first[1]; v <= hi[1] + Slack(lo[1], hi[1]); v += kTwoPi) {
      const double turn[2] = {std::clamp(u, lo[0], hi[0]), std::clamp(v, lo[1], hi[1])};
      double ref[2];
      for (int d = 0; d < 2; ++d) ref[d] = ReferenceOfOwn(cell.paramLo[d], cell.paramScale[d], cell.angular[d], turn[d]);
      if (cell.trim->Admits(ref)) {
        own[0] = turn[0];
        own[1] = turn[1];
        return true;
      }
      if (!periodic[1]) break;
    }
    if (!periodic[0]) break;
  }
  return false;
}

}  // namespace

void AnalyticSurface::Evaluate(double u, double v, double* xyz) const {
  double a = 0.0, b = 0.0, c = 0.0;  // along x, y, z
  switch (kind) {
    case Kind::Plane:
      a = u;
      b = v;
      break;
    case Kind::Cylinder:
      a = radius * std::cos(u);
      b = radius * std::sin(u);
      c = v;
      break;
    case Kind::Cone: {
      const double r = radius + v * sinAngle;
      a = r * std::cos(u);
      b = r * std::sin(u);
      c = v * cosAngle;
      break;
    }
    case Kind::Sphere:
      a = radius * std::cos(v) * std::cos(u);
      b = radius * std::cos(v) * std::sin(u);
      c = radius * std::sin(v);
      break;
    case Kind::Torus: {
      const double r = radius + minorRadius * std::cos(v);
      a = r * std::cos(u);
      b = r * std::sin(u);
      c = minorRadius * std::sin(v);
      break;
    }
  }
  for (int k = 0; k < 3; ++k) xyz[k] = origin[k] + a * x[k] + b * y[k] + c * z[k];
}

void SurfaceFoot(const AnalyticCell& cell, const double* point, double* own) {
  const AnalyticSurface& s = *cell.surface;
  const Box box = BoxOf(cell);
  const Local l = ToLocal(s, point);
  const double uc = 0.5 * (box.u0 + box.u1), vc = 0.5 * (box.v0 + box.v1);
  const auto nearBox = [](double theta, double centre) { return NearestAngle(theta, centre - M_PI, centre + M_PI); };
  switch (s.kind) {
    case AnalyticSurface::Kind::Plane:
      own[0] = l.x;
      own[1] = l.y;
      return;
    case AnalyticSurface::Kind::Cylinder:
      own[0] = nearBox(l.phi, uc);
      own[1] = l.z;
      return;
    case AnalyticSurface::Kind::Cone: {
      const bool beyondApex = s.radius + vc * s.sinAngle < 0.0;
      own[0] = nearBox(beyondApex ? l.phi + M_PI : l.phi, uc);
      own[1] = (l.rho * std::cos(own[0] - l.phi) - s.radius) * s.sinAngle + l.z * s.cosAngle;
      return;
    }
    case AnalyticSurface::Kind::Sphere:
      own[0] = nearBox(l.phi, uc);
      own[1] = std::atan2(l.z, l.rho);
      return;
    case AnalyticSurface::Kind::Torus: {
      const bool inner = s.radius + s.minorRadius * std::cos(vc) < 0.0;
      own[0] = nearBox(inner ? l.phi + M_PI : l.phi, uc);
      own[1] = nearBox(std::atan2(l.z, l.rho * std::cos(own[0] - l.phi) - s.radius), vc);
      return;
    }
  }
}

bool ClosedFormCovers(const AnalyticCell& cell) {
  const AnalyticSurface& s = *cell.surface;
  const Box box = BoxOf(cell);
  if (s.kind == AnalyticSurface::Kind::Cone) return !ApexInBox(s, box);
  if (s.kind == AnalyticSurface::Kind::Torus) return ParallelsSign(s, box) != 0;
  if (s.kind == AnalyticSurface::Kind::Sphere) return WithinLatitudes(box);
  return true;
}

bool SolveAnalyticCell(const AnalyticCell& cell, const double* point, double bound2, CellSolveResult* result) {
  if (!(std::isfinite(point[0]) && std::isfinite(point[1]) && std::isfinite(point[2]))) return false;
  const AnalyticSurface& s = *cell.surface;
  const Box box = BoxOf(cell);
  const Local l = ToLocal(s, point);
  double own[2];
  if (!BoxMinimum(s, box, l, own)) return false;
  CellSolveResult r;
  if (!cell.trim) {
    if (!Answer(cell, point, own, bound2, &r)) r.status = PointStatus::Farther;
    *result = r;
    return true;
  }
  if (AdmittedTurn(cell, box, own)) {
    if (!Answer(cell, point, own, bound2, &r)) r.status = PointStatus::Farther;
    *result = r;
    return true;
  }
  // The box's minimum is outside the region: the cell's answer, if any, is
  // a stationary point the region holds (the edges answer its boundary).
  double stationary[4][2];
  const int count = StationaryPoints(s, box, l, stationary);
  if (count < 0) return false;
  r.status = PointStatus::Farther;
  for (int i = 0; i < count; ++i) {
    if (!AdmittedTurn(cell, box, stationary[i])) continue;
    CellSolveResult candidate;
    if (!Answer(cell, point, stationary[i], bound2, &candidate)) continue;
    if (r.status == PointStatus::Farther || candidate.distance < r.distance) r = candidate;
  }
  *result = r;
  return true;
}

}  // namespace invmap::kernels
