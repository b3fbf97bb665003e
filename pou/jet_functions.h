// Elementary functions of jets (pou/jet.h).
#pragma once

#include <cmath>

#include "pou/jet.h"

namespace invmap::pou {

// The scalar functions under one spelling for the templates.
inline double Sqrt(double x) { return std::sqrt(x); }
inline double Sin(double x) { return std::sin(x); }
inline double Cos(double x) { return std::cos(x); }
inline double Atan2(double y, double x) { return std::atan2(y, x); }

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
