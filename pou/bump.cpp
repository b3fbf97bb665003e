#include "pou/bump.h"

#include <cmath>

namespace invmap::pou {
namespace {

constexpr double kSpan = kBumpOuter - kBumpInner;
/// t where xi' is least (H = 1/2).
constexpr double kSteepest = kBumpInner + 0.5 * kSpan;

/// A point value of the closed forms, widened for their rounding: exp of a
/// sum of terms up to about 700 in size loses up to about 1e-13 relative.
Interval Widen(double x) { return {x - 1e-11 * std::fabs(x) - 1e-300, x + 1e-11 * std::fabs(x) + 1e-300}; }

/// The t in (1/4, 5/8) where xi'' is least (golden-section search; xi'' is
/// flat there, so an error of the location changes the value only to second
/// order, far below the widening of Widen).
double LeastSecondDerivativeAt() {
  double a = kBumpInner, b = kSteepest;
  const double ratio = 0.5 * (std::sqrt(5.0) - 1.0);
  double c = b - ratio * (b - a), d = a + ratio * (b - a);
  for (int i = 0; i < 200 && b - a > 1e-15; ++i) {
    if (Bump(c).f2 < Bump(d).f2) {
      b = d;
    } else {
      a = c;
    }
    c = b - ratio * (b - a);
    d = a + ratio * (b - a);
  }
  return 0.5 * (a + b);
}

}  // namespace

BumpValues Bump(double t) {
  const double h = (t - kBumpInner) / kSpan;
  if (!(h > 0.0)) return {1.0, 0.0, 0.0};
  if (!(h < 1.0)) return {0.0, 0.0, 0.0};
  const double g = 2.0 / std::sqrt(1.0 - h) - 2.0 / std::sqrt(h);  // 2 s
  BumpValues b;
  b.f = 1.0 / (1.0 + std::exp(g));
  // xi (1 - xi) in logarithms, so that tiny values times the huge powers of
  // 1/h near the ends neither underflow to 0 * inf nor overflow.
  const double logW = -std::fabs(g) - 2.0 * std::log1p(std::exp(-std::fabs(g)));
  const double gp = std::pow(1.0 - h, -1.5) + std::pow(h, -1.5);
  const double gpp = 1.5 * (std::pow(1.0 - h, -2.5) - std::pow(h, -2.5));
  const double dxi = -std::exp(logW + std::log(gp));
  const double wgp2 = std::exp(logW + 2.0 * std::log(gp));
  const double wgpp = gpp == 0.0 ? 0.0 : std::copysign(std::exp(logW + std::log(std::fabs(gpp))), gpp);
  const double ddxi = (1.0 - 2.0 * b.f) * wgp2 - wgpp;
  b.f1 = dxi / kSpan;
  b.f2 = ddxi / (kSpan * kSpan);
  return b;
}

BumpRanges Bump(const Interval& t) {
  static const double leastSecond = LeastSecondDerivativeAt();
  static const double greatestSecond = 2.0 * kSteepest - leastSecond;  // by symmetry
  const BumpValues lo = Bump(t.lo), hi = Bump(t.hi);
  BumpRanges r;
  r.f = Hull(Widen(lo.f), Widen(hi.f));
  r.f = {std::max(0.0, r.f.lo), std::min(1.0, r.f.hi)};
  r.f1 = Hull(Widen(lo.f1), Widen(hi.f1));
  if (t.contains(kSteepest)) r.f1 = Hull(r.f1, Widen(Bump(kSteepest).f1));
  r.f1.hi = std::min(r.f1.hi, 0.0);
  r.f2 = Hull(Widen(lo.f2), Widen(hi.f2));
  if (t.contains(leastSecond)) r.f2 = Hull(r.f2, Widen(Bump(leastSecond).f2 * (1.0 + 1e-9)));
  if (t.contains(greatestSecond)) r.f2 = Hull(r.f2, Widen(Bump(greatestSecond).f2 * (1.0 + 1e-9)));
  return r;
}

}  // namespace invmap::pou
