// Interval arithmetic with outward rounding: every operation returns an
// interval that contains the exact result for all arguments in its operands'
// intervals. Arithmetic is done in round-to-nearest and each bound moved one
// ulp outward (nextafter), which holds because round-to-nearest is within
// half an ulp. Library functions (exp, sin, cos, atan2) are taken to be
// within 4 ulps of the exact value (glibc documents at most 1 to 2 ulps on
// x86-64 for these) and widened by that much; sqrt is correctly rounded.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace invmap::pou {

struct Interval {
  double lo = 0.0;
  double hi = 0.0;

  Interval() = default;
  /// The point interval [x, x] (exact: no rounding is involved).
  explicit Interval(double x) : lo(x), hi(x) {}
  Interval(double low, double high) : lo(low), hi(high) {}

  double mid() const { return 0.5 * (lo + hi); }
  double width() const { return hi - lo; }
  double mag() const { return std::max(std::fabs(lo), std::fabs(hi)); }
  bool contains(double x) const { return lo <= x && x <= hi; }
};

namespace interval_detail {
constexpr double kInf = std::numeric_limits<double>::infinity();
inline double Down(double x) { return std::nextafter(x, -kInf); }
inline double Up(double x) { return std::nextafter(x, kInf); }
/// Widening of a library function's result: 4 ulps relative, plus the
/// smallest subnormal so that results near 0 widen too.
inline double LibDown(double x) { return Down(x - std::fabs(x) * 0x1p-50 - 0x1p-1074); }
inline double LibUp(double x) { return Up(x + std::fabs(x) * 0x1p-50 + 0x1p-1074); }
}  // namespace interval_detail

inline Interval operator+(const Interval& a, const Interval& b) {
  return {interval_detail::Down(a.lo + b.lo), interval_detail::Up(a.hi + b.hi)};
}
inline Interval operator-(const Interval& a, const Interval& b) {
  return {interval_detail::Down(a.lo - b.hi), interval_detail::Up(a.hi - b.lo)};
}
inline Interval operator-(const Interval& a) { return {-a.hi, -a.lo}; }
inline Interval operator*(const Interval& a, const Interval& b) {
  const double p[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi};
  double lo = std::min({p[0], p[1], p[2], p[3]});
  double hi = std::max({p[0], p[1], p[2], p[3]});
  // 0 * inf is NaN; an operand with an infinite bound gives the whole line.
  if (std::isnan(lo) || std::isnan(hi)) return {-interval_detail::kInf, interval_detail::kInf};
  return {interval_detail::Down(lo), interval_detail::Up(hi)};
}
inline Interval operator/(const Interval& a, const Interval& b) {
  if (b.lo <= 0.0 && b.hi >= 0.0) return {-interval_detail::kInf, interval_detail::kInf};
  const double q[4] = {a.lo / b.lo, a.lo / b.hi, a.hi / b.lo, a.hi / b.hi};
  double lo = std::min({q[0], q[1], q[2], q[3]});
  double hi = std::max({q[0], q[1], q[2], q[3]});
  if (std::isnan(lo) || std::isnan(hi)) return {-interval_detail::kInf, interval_detail::kInf};
  return {interval_detail::Down(lo), interval_detail::Up(hi)};
}

/// The smallest interval holding both.
inline Interval Hull(const Interval& a, const Interval& b) { return {std::min(a.lo, b.lo), std::max(a.hi, b.hi)}; }
/// The common part (the caller knows it is not empty).
inline Interval Intersect(const Interval& a, const Interval& b) {
  return {std::max(a.lo, b.lo), std::min(a.hi, b.hi)};
}
/// x^2 over the interval (tighter than x * x when it holds 0).
inline Interval Square(const Interval& a) {
  const double l = std::fabs(a.lo), h = std::fabs(a.hi);
  const double top = interval_detail::Up(std::max(l, h) * std::max(l, h));
  if (a.lo <= 0.0 && a.hi >= 0.0) return {0.0, top};
  return {interval_detail::Down(std::min(l, h) * std::min(l, h)), top};
}
inline Interval Sqrt(const Interval& a) {
  return {interval_detail::Down(std::sqrt(std::max(a.lo, 0.0))), interval_detail::Up(std::sqrt(std::max(a.hi, 0.0)))};
}
inline Interval Exp(const Interval& a) {
  return {std::max(0.0, interval_detail::LibDown(std::exp(a.lo))), interval_detail::LibUp(std::exp(a.hi))};
}
/// Widens a value computed by library calls (4 ulps either way).
inline Interval LibraryValue(double x) { return {interval_detail::LibDown(x), interval_detail::LibUp(x)}; }

/// sin and cos over an interval: the values at the ends, and +-1 where the
/// interval holds a maximum or minimum.
inline Interval Sin(const Interval& a) {
  if (!(a.width() < 6.0)) return {-1.0, 1.0};
  constexpr double kPi = 3.141592653589793;
  Interval r = Hull(LibraryValue(std::sin(a.lo)), LibraryValue(std::sin(a.hi)));
  // Extrema at pi/2 + k pi; k is judged with a margin so rounding of the
  // ends never hides one (an extra +-1 only widens the result).
  const double first = std::floor((a.lo - kPi / 2) / kPi - 1e-9);
  for (double k = first; k * kPi + kPi / 2 <= a.hi + 1e-9; k += 1.0) {
    const double at = k * kPi + kPi / 2;
    if (at >= a.lo - 1e-9) {
      if (std::fmod(std::fabs(k), 2.0) == 0.0) {
        r.hi = 1.0;
      } else {
        r.lo = -1.0;
      }
    }
  }
  return {std::max(r.lo, -1.0), std::min(r.hi, 1.0)};
}
inline Interval Cos(const Interval& a) {
  constexpr double kHalfPi = 1.5707963267948966;
  // cos x = sin(x + pi/2); the shift's rounding is absorbed by widening.
  return Sin(Interval(interval_detail::Down(a.lo + kHalfPi) - 1e-15, interval_detail::Up(a.hi + kHalfPi) + 1e-15));
}

}  // namespace invmap::pou
