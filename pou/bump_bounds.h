// Bounds of the bump function xi and its first three derivatives over an
// interval of t, for the derivative bounds of the blended parametrizations
// (pou/piece_bounds.h).
//
// With H = (t - 1/4) / (3/4) and g(H) = 2 / sqrt(1 - H) - 2 / sqrt(H),
// xi = sigma(g) for the logistic sigma(x) = 1 / (1 + e^x), whose
// derivatives are L, L |1 - 2 sigma|, L |1 - 6 L| and at most 2 L |1 - 2
// sigma| in size, L = sigma (1 - sigma) <= e^-|x|. A table holds bounds for
// 2048 cells of H, finer near 0 and 1 where the derivatives peak (H = (1 -
// cos(pi i / 2048)) / 2): for each derivative, the larger of its values at
// the cell's ends plus half the cell's width times a bound of the next
// derivative over the cell (the chain rule with each factor at its largest
// there: g increases, and g', g'', g''', g'''' are sums or differences of
// powers of H and 1 - H). An interval of t takes the largest over the cells
// it meets (blocks of 32 cells keep their largest, for long intervals). The
// two end cells (H within 6e-7 of 0 or 1) hold derivatives below e^-2000,
// which underflow: they get the smallest normal double.
#pragma once

namespace invmap::pou {

/// Upper bounds of |xi|, |xi'|, |xi''|, |xi'''| (derivatives in t) over an interval.
struct BumpDerivativeBounds {
  double d[4] = {0, 0, 0, 0};
};

/// Bounds over [t0, t1] (t0 <= t1; any values: xi is 1 below 1/4 and 0 above 1).
BumpDerivativeBounds BoundBump(double t0, double t1);

}  // namespace invmap::pou
