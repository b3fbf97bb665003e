// Interval arithmetic with outward rounding: every operation returns an
// interval that contains the exact result for all arguments in its operands'
// intervals. Arithmetic is done in round-to-nearest and each bound moved one
// ulp outward (nextafter), which holds because round-to-nearest is within
// half an ulp.
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

  double mag() const { return std::max(std::fabs(lo), std::fabs(hi)); }
};

namespace interval_detail {
constexpr double kInf = std::numeric_limits<double>::infinity();
inline double Down(double x) { return std::nextafter(x, -kInf); }
inline double Up(double x) { return std::nextafter(x, kInf); }
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

/// x^2 over the interval (tighter than x * x when it holds 0).
inline Interval Square(const Interval& a) {
  const double l = std::fabs(a.lo), h = std::fabs(a.hi);
  const double top = interval_detail::Up(std::max(l, h) * std::max(l, h));
  if (a.lo <= 0.0 && a.hi >= 0.0) return {0.0, top};
  return {interval_detail::Down(std::min(l, h) * std::min(l, h)), top};
}

}  // namespace invmap::pou
