// Elementary functions of jets (pou/jet.h) for both scalars: double (point
// evaluation) and Interval (enclosures over a box, pou/interval.h).
#pragma once

#include <cmath>

#include "pou/interval.h"
#include "pou/jet.h"

namespace invmap::pou {

// The scalar functions under both names, so templates call one spelling.
inline double Sqrt(double x) { return std::sqrt(x); }
inline double Sin(double x) { return std::sin(x); }
inline double Cos(double x) { return std::cos(x); }
inline double Atan2(double y, double x) { return std::atan2(y, x); }

/// atan2 over a box of (y, x): the corner values when the box avoids the
/// origin and does not cross the negative x axis (the angle then has its
/// extremes at corners), otherwise [-pi, pi].
inline Interval Atan2(const Interval& y, const Interval& x) {
  constexpr double kPi = 3.141592653589793;
  const Interval whole(-interval_detail::Up(kPi), interval_detail::Up(kPi));
  const bool holdsOrigin = x.contains(0.0) && y.contains(0.0);
  const bool crossesCut = x.lo < 0.0 && y.lo <= 0.0 && y.hi >= 0.0;
  if (holdsOrigin || crossesCut) return whole;
  Interval r = LibraryValue(std::atan2(y.lo, x.lo));
  r = Hull(r, LibraryValue(std::atan2(y.lo, x.hi)));
  r = Hull(r, LibraryValue(std::atan2(y.hi, x.lo)));
  r = Hull(r, LibraryValue(std::atan2(y.hi, x.hi)));
  return r;
}

template <typename S>
Jet<S> JetSqrt(const Jet<S>& a) {
  const S f = Sqrt(a.v);
  const S f1 = S(0.5) / f;
  const S f2 = -(f1 / (S(2.0) * a.v));
  return Compose(a, f, f1, f2);
}

template <typename S>
Jet<S> JetReciprocal(const Jet<S>& a) {
  const S f = S(1.0) / a.v;
  const S f1 = -(f * f);
  const S f2 = S(2.0) * (f * f * f);
  return Compose(a, f, f1, f2);
}

template <typename S>
Jet<S> JetCos(const Jet<S>& a) {
  const S c = Cos(a.v), s = Sin(a.v);
  return Compose(a, c, -s, -c);
}

template <typename S>
Jet<S> JetSin(const Jet<S>& a) {
  const S c = Cos(a.v), s = Sin(a.v);
  return Compose(a, s, c, -s);
}

/// The angle of (x, y), atan2(y, x), with its derivatives; (x, y) must stay
/// away from the origin.
template <typename S>
Jet<S> JetAtan2(const Jet<S>& y, const Jet<S>& x) {
  const S r2 = x.v * x.v + y.v * y.v;
  const S r2u = S(2.0) * (x.v * x.du + y.v * y.du);
  const S r2v = S(2.0) * (x.v * x.dv + y.v * y.dv);
  const S nu = x.v * y.du - y.v * x.du;
  const S nv = x.v * y.dv - y.v * x.dv;
  Jet<S> r;
  r.v = Atan2(y.v, x.v);
  r.du = nu / r2;
  r.dv = nv / r2;
  const S r4 = r2 * r2;
  r.duu = (x.v * y.duu - y.v * x.duu) / r2 - nu * r2u / r4;
  r.duv = (x.dv * y.du - y.dv * x.du + x.v * y.duv - y.v * x.duv) / r2 - nu * r2v / r4;
  r.dvv = (x.v * y.dvv - y.v * x.dvv) / r2 - nv * r2v / r4;
  return r;
}

}  // namespace invmap::pou
