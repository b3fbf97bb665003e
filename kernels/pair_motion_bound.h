// How far two moving subdomains can have come closer since a bound of their
// distance was proved: a first-order bound from where they were (a box of
// each side's points) and how each side has moved since.
//
// With x and y points of the two subdomains when the bound L was proved and
// x + dx, y + dy the same points now (dx = (R_now R_then^T - I)(x - t_then)
// + t_now - t_then for a side moved from (R_then, t_then) to (R_now, t_now)),
//   |x + dx - y - dy|^2 = |x - y|^2 + 2 (x - y).(dx - dy) + |dx - dy|^2
//                      >= L^2 + 2 (x - y).(dx - dy),
// whose last term is bounded below over the two boxes in interval
// arithmetic. A motion across the line between the subdomains (a model
// sliding along another) barely changes their distance, where the drift of
// their points (engine/pair_bound_cache.h) charges all of it.
#pragma once

#include "kernels/pair_problem.h"

namespace invmap::kernels {

/// Doubles of a SubdomainPlace: both sides' boxes (lo, hi) and motions.
constexpr int kSubdomainPlaceSize = 2 * 6 + 2 * 12;

/// Writes where two subdomains are: side s's box [lo[s], hi[s]] (common
/// frame) and its motion, into `place` (kSubdomainPlaceSize doubles).
void WriteSubdomainPlace(const double lo[2][3], const double hi[2][3], const RigidMotion& a, const RigidMotion& b,
                         double* place);

/// A lower bound of |x' - y'|^2 - |x - y|^2 over the points of the two
/// boxes of `place`, moved from the motions there to `a` and `b` (<= 0
/// when the subdomains may have come closer).
double SquaredDistanceChangeBound(const double* place, const RigidMotion& a, const RigidMotion& b);

}  // namespace invmap::kernels
