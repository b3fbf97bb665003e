#include "pou/enclosure.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "pou/blend.h"
#include "pou/bump.h"
#include "pou/chart_maps.h"

namespace invmap::pou {
namespace {

constexpr double kOwnOnly = 0.1547;  // as in pou_surface.cpp: no neighbour reaches inside this share of R
constexpr double kUnit = 0x1p-52;

Jet<Interval> HullJet(const Jet<Interval>& a, const Jet<Interval>& b) {
  return {Hull(a.v, b.v), Hull(a.du, b.du), Hull(a.dv, b.dv), Hull(a.duu, b.duu), Hull(a.duv, b.duv), Hull(a.dvv, b.dvv)};
}

/// The shape function of chart z and its derivatives over the box (qx, qy)
/// (cut to the chart's square, where every point with a positive weight
/// lies). False when nothing of the box is left. The ranges of the net cut
/// to the box (RangeOverBox) are intersected with a Taylor expansion at the
/// box's centre whose remainder uses the third partials over the box (or,
/// for a box narrower than 1e-3 R, over one that wide around it, so that the
/// cut's rounding, amplified by the inverse widths, stays small).
bool ShapeOver(const PouSurface& surface, std::int64_t z, Interval qx, Interval qy, ShapeDerivatives<Interval>* out) {
  const double r = surface.radius(z);
  qx = Intersect(qx, Interval(-r, r));
  qy = Intersect(qy, Interval(-r, r));
  if (!(qx.lo <= qx.hi) || !(qy.lo <= qy.hi)) return false;
  const ShapeNet net = surface.net(z);
  const double minWidth = 1e-3 * r;
  double lo[2] = {qx.lo, qy.lo}, hi[2] = {qx.hi, qy.hi};
  for (int i = 0; i < 2; ++i) {
    if (hi[i] - lo[i] < minWidth) {
      const double mid = 0.5 * (lo[i] + hi[i]);
      lo[i] = std::max(-r, mid - minWidth);
      hi[i] = std::min(r, mid + minWidth);
    }
  }
  const ShapeRanges wide = RangeOverBox(net, lo, hi);
  const double cx = qx.mid(), cy = qy.mid();
  const double hx = interval_detail::Up(std::max(cx - qx.lo, qx.hi - cx));
  const double hy = interval_detail::Up(std::max(cy - qy.lo, qy.hi - cy));
  const ShapeJet at = EvaluateShape(net, cx, cy);
  const double d = surface.degree(z) + 1.0;
  // Rounding of the evaluation at the centre: sums of d^2 products whose
  // basis weights add up to 1 (value), or to at most 2 d / (2 R) per
  // derivative order.
  const double slack0 = 64.0 * d * d * kUnit * surface.shapeBounds(z).value;
  const double slack1 = slack0 * d / r;
  const double slack2 = slack1 * d / r;
  const double e = interval_detail::Up(hx + hy);
  const double m3 = wide.third;
  const Interval dx(-hx, hx), dy(-hy, hy);
  const Interval half(0.5), two(2.0);
  const double rem0 = interval_detail::Up(m3 * e * e * e / 6.0 * (1 + 1e-12) + slack0);
  const double rem1 = interval_detail::Up(m3 * e * e / 2.0 * (1 + 1e-12) + slack1);
  const double rem2 = interval_detail::Up(m3 * e * (1 + 1e-12) + slack2);
  for (int c = 0; c < 3; ++c) {
    const Interval gx(at.grad[c][0]), gy(at.grad[c][1]);
    const Interval hxx(at.hess[c][0]), hxy(at.hess[c][1]), hyy(at.hess[c][2]);
    const Interval value = Interval(at.value[c]) + gx * dx + gy * dy +
                           half * (hxx * Square(dx) + two * (hxy * (dx * dy)) + hyy * Square(dy)) +
                           Interval(-rem0, rem0);
    const auto meet = [](const Interval& a, const Interval& b) {
      const Interval m = Intersect(a, b);
      return m.lo <= m.hi ? m : a;  // both hold the true range; empty only through rounding
    };
    out->value[c] = meet(value, wide.value[c]);
    out->grad[c][0] = meet(gx + hxx * dx + hxy * dy + Interval(-rem1, rem1), wide.grad[c][0]);
    out->grad[c][1] = meet(gy + hxy * dx + hyy * dy + Interval(-rem1, rem1), wide.grad[c][1]);
    out->hess[c][0] = meet(hxx + Interval(-rem2, rem2), wide.hess[c][0]);
    out->hess[c][1] = meet(hxy + Interval(-rem2, rem2), wide.hess[c][1]);
    out->hess[c][2] = meet(hyy + Interval(-rem2, rem2), wide.hess[c][2]);
  }
  return true;
}

/// True when some angle of [lo, hi] (radians, any branch) is within `reach`
/// of `angle` modulo 2 pi.
bool WithinAngle(const Interval& a, double angle, double reach) {
  for (int k = -1; k <= 1; ++k) {
    const double e = angle + 2.0 * kPi * k;
    if (a.lo - reach <= e && e <= a.hi + reach) return true;
  }
  return false;
}

}  // namespace

ThetaEnclosure Enclose(const PouSurface& surface, std::int64_t chart, const ChartBox& box) {
  const int n = surface.valence(chart);
  const double r = surface.radius(chart);
  const Interval x(box.lo[0], box.hi[0]), y(box.lo[1], box.hi[1]);
  const JetPoint<Interval> p{Jet<Interval>::Variable(x, 0), Jet<Interval>::Variable(y, 1)};
  ThetaEnclosure out;
  Jet<Interval> own[3];
  ShapeDerivatives<Interval> psi;
  ShapeOver(surface, chart, x, y, &psi);
  ComposeShape(psi, p, own);

  // Distances of the box from the chart's centre.
  const double nearX = x.contains(0.0) ? 0.0 : std::min(std::fabs(x.lo), std::fabs(x.hi));
  const double nearY = y.contains(0.0) ? 0.0 : std::min(std::fabs(y.lo), std::fabs(y.hi));
  const double nearest = interval_detail::Down(std::hypot(nearX, nearY));
  const double farthest = interval_detail::Up(std::hypot(x.mag(), y.mag()));
  const double ownOnly = kOwnOnly * r;
  if (farthest < ownOnly) {
    for (int c = 0; c < 3; ++c) out.x[c] = own[c];
    return out;
  }
  // Polar coordinates of the box's points outside the own-only disk.
  const double rMin = std::max(nearest, ownOnly);
  Interval r2 = Square(x) + Square(y);
  r2.lo = std::max(r2.lo, interval_detail::Down(rMin * rMin));
  const Interval rr(rMin, farthest);
  Jet<Interval> radius;
  radius.v = rr;
  radius.du = x / rr;
  radius.dv = y / rr;
  const Interval r3 = rr * r2;
  radius.duu = Square(y) / r3;
  radius.duv = -(x * y) / r3;
  radius.dvv = Square(x) / r3;
  Jet<Interval> angle;  // derivatives of atan2(y, x); values set per edge
  const Interval r4 = r2 * r2;
  angle.du = -y / r2;
  angle.dv = x / r2;
  angle.duu = Interval(2.0) * (x * y) / r4;
  angle.duv = (Square(y) - Square(x)) / r4;
  angle.dvv = -(Interval(2.0) * (x * y) / r4);

  const Jet<Interval> ownWeight = JetBump(Constant(1.0 / r, Interval()) * radius);
  const Interval boxAngle = nearest > 0.0 ? Atan2(y, x) : Interval(-2 * kPi, 2 * kPi);
  const double reach = 3.0 * kPi / n;
  std::vector<Contribution<Interval>> others;
  for (int edge = 0; edge < n; ++edge) {
    if (!WithinAngle(boxAngle, 2.0 * kPi * edge / n, reach + 1e-9)) continue;
    // The angle from the edge: the rotated box's, cut to the gluing domain's |a| < 3 pi / n.
    const JetPoint<Interval> turned = ToEdgeDirection(n, edge, p);
    const Interval fromEdge = nearest > 0.0 ? Atan2(turned.y.v, turned.x.v) : Interval(-kPi, kPi);
    const bool partial = !(fromEdge.lo > -reach && fromEdge.hi < reach) || nearest < ownOnly;
    const Interval cut = Intersect(fromEdge, Interval(-reach, reach));
    if (!(cut.lo <= cut.hi)) continue;
    Jet<Interval> a = angle;
    a.v = cut;
    const Jet<Interval> distance = Constant(kFrameRadius / r, Interval()) * radius;
    const Jet<Interval> unfolded = Constant(n / 6.0, Interval()) * a;
    const JetPoint<Interval> frame{distance * JetCos(unfolded), distance * JetSin(unfolded)};
    const JetPoint<Interval> other = HalfTurn(frame);
    const Jet<Interval> otherDistance = JetSqrt(other.x * other.x + other.y * other.y);
    if (!(otherDistance.v.lo < kFrameRadius)) continue;
    Contribution<Interval> contribution;
    contribution.weight = JetBump(Constant(1.0 / kFrameRadius, Interval()) * otherDistance);
    if (contribution.weight.v.hi <= 0.0) continue;
    const std::int64_t z = surface.mesh().neighbor(chart, edge);
    const JetPoint<Interval> q = FromFrame(surface.valence(z), surface.mesh().mate(chart, edge), other);
    ShapeDerivatives<Interval> psiZ;
    if (!ShapeOver(surface, z, q.x.v, q.y.v, &psiZ)) continue;
    ComposeShape(psiZ, q, contribution.point);
    if (partial) contribution.weight = HullJet(contribution.weight, Jet<Interval>::Constant(Interval(0.0)));
    others.push_back(contribution);
  }
  Blend(ownWeight, own, others, out.x);
  if (nearest < ownOnly) {
    for (int c = 0; c < 3; ++c) out.x[c] = HullJet(out.x[c], own[c]);
  }
  return out;
}

}  // namespace invmap::pou
