// Second-order jets in two variables (u, v): a value with its first and
// second partial derivatives, propagated through arithmetic by the chain
// rule.
#pragma once

namespace invmap::pou {

template <typename S>
struct Jet {
  S v{};                   ///< Value.
  S du{}, dv{};            ///< First partials.
  S duu{}, duv{}, dvv{};   ///< Second partials.

  static Jet Constant(const S& value) {
    Jet j;
    j.v = value;
    return j;
  }
  /// The coordinate u (index 0) or v (index 1) itself, taking `value`.
  static Jet Variable(const S& value, int index) {
    Jet j;
    j.v = value;
    (index == 0 ? j.du : j.dv) = S(1.0);
    return j;
  }
};

/// A point of a chart as two jets.
template <typename S>
struct JetPoint {
  Jet<S> x, y;
};

template <typename S>
Jet<S> operator+(const Jet<S>& a, const Jet<S>& b) {
  return {a.v + b.v, a.du + b.du, a.dv + b.dv, a.duu + b.duu, a.duv + b.duv, a.dvv + b.dvv};
}
template <typename S>
Jet<S> operator-(const Jet<S>& a, const Jet<S>& b) {
  return {a.v - b.v, a.du - b.du, a.dv - b.dv, a.duu - b.duu, a.duv - b.duv, a.dvv - b.dvv};
}
template <typename S>
Jet<S> operator-(const Jet<S>& a) {
  return {-a.v, -a.du, -a.dv, -a.duu, -a.duv, -a.dvv};
}
template <typename S>
Jet<S> operator+(const Jet<S>& a, const S& c) {
  Jet<S> r = a;
  r.v = a.v + c;
  return r;
}
/// Scaling by a constant.
template <typename S>
Jet<S> operator*(const S& c, const Jet<S>& a) {
  return {c * a.v, c * a.du, c * a.dv, c * a.duu, c * a.duv, c * a.dvv};
}
template <typename S>
Jet<S> operator*(const Jet<S>& a, const Jet<S>& b) {
  return {a.v * b.v,
          a.du * b.v + a.v * b.du,
          a.dv * b.v + a.v * b.dv,
          a.duu * b.v + S(2.0) * (a.du * b.du) + a.v * b.duu,
          a.duv * b.v + a.du * b.dv + a.dv * b.du + a.v * b.duv,
          a.dvv * b.v + S(2.0) * (a.dv * b.dv) + a.v * b.dvv};
}

/// f(a) given f, f' and f'' at a's value.
template <typename S>
Jet<S> Compose(const Jet<S>& a, const S& f, const S& f1, const S& f2) {
  return {f,
          f1 * a.du,
          f1 * a.dv,
          f2 * (a.du * a.du) + f1 * a.duu,
          f2 * (a.du * a.dv) + f1 * a.duv,
          f2 * (a.dv * a.dv) + f1 * a.dvv};
}

}  // namespace invmap::pou
