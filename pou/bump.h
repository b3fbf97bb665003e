// The bump function of the construction: xi(t) = 1 for t <= 1/4, 0 for
// t >= 1, and 1 / (1 + e^(2 s)) between, with s = 1/sqrt(1 - H) - 1/sqrt(H)
// and H = (t - 1/4) / (3/4). C-infinity: every derivative vanishes at 1/4
// and at 1. The bump of a chart is xi(|p| / R) (R its p-domain's radius).
#pragma once

#include "pou/interval.h"
#include "pou/jet.h"

namespace invmap::pou {

/// Inner and outer radius of the bump, as fractions of the p-domain radius.
constexpr double kBumpInner = 0.25;
constexpr double kBumpOuter = 1.0;

/// xi and its first and second derivatives at t.
struct BumpValues {
  double f = 0.0, f1 = 0.0, f2 = 0.0;
};
BumpValues Bump(double t);

/// Rigorous ranges of xi, xi' and xi'' over [t.lo, t.hi]. They use the
/// shape of xi: it decreases; xi' has one minimum (t = 5/8, by the symmetry
/// xi(H) + xi(1 - H) = 1); xi'' has one minimum on (1/4, 5/8) and one
/// maximum on (5/8, 1) (tests/pou/bump_test.cpp checks all three).
struct BumpRanges {
  Interval f, f1, f2;
};
BumpRanges Bump(const Interval& t);

/// xi of a jet (the jet's value must be positive where xi is not constant).
inline Jet<double> JetBump(const Jet<double>& t) {
  const BumpValues b = Bump(t.v);
  return Compose(t, b.f, b.f1, b.f2);
}
inline Jet<Interval> JetBump(const Jet<Interval>& t) {
  const BumpRanges b = Bump(t.v);
  return Compose(t, b.f, b.f1, b.f2);
}

}  // namespace invmap::pou
