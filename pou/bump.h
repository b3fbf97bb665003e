// The bump function of the construction: xi(t) = 1 for t <= 1/4, 0 for
// t >= 1, and 1 / (1 + e^(2 s)) between, with s = 1/sqrt(1 - H) - 1/sqrt(H)
// and H = (t - 1/4) / (3/4). C-infinity: every derivative vanishes at 1/4
// and at 1. The bump of a chart is xi(|p| / R) (R its p-domain's radius).
#pragma once

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

/// xi of a jet (the jet's value must be positive where xi is not constant).
inline Jet<double> JetBump(const Jet<double>& t) {
  const BumpValues b = Bump(t.v);
  return Compose(t, b.f, b.f1, b.f2);
}

}  // namespace invmap::pou
