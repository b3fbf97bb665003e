// Rigorous enclosures of theta_v and its first and second derivatives over
// a box of a chart's coordinates: the formulas of PouSurface::Evaluate run in
// interval arithmetic (pou/interval.h), with
//  - the shape functions bounded by their Taylor expansion at the box's
//    centre plus a remainder from a bound of their third derivatives over
//    the whole chart square (pou/shape_function.h BoundShape), intersected
//    with the global bounds of their values and derivatives;
//  - the bump's ranges from its shape (pou/bump.h);
//  - the chart's centre, where polar coordinates are not smooth, handled by
//    its own-only disk: inside |p| < 0.1547 R theta_v is psi_v, so a box
//    reaching in there is enclosed by the hull of psi_v's enclosure and the
//    blend's over the box's points outside that disk;
//  - a neighbour that contributes on part of the box only: its weight's
//    enclosure is joined with 0 (the weight and all its derivatives vanish
//    outside the gluing domain).
#pragma once

#include <cstdint>

#include "pou/interval.h"
#include "pou/jet.h"
#include "pou/pou_surface.h"

namespace invmap::pou {

/// A box of chart coordinates.
struct ChartBox {
  double lo[2], hi[2];
  double mid(int i) const { return 0.5 * (lo[i] + hi[i]); }
  bool contains(double u, double v) const { return lo[0] <= u && u <= hi[0] && lo[1] <= v && v <= hi[1]; }
};

/// Ranges over a box of theta_v's coordinates (value) and their partials.
struct ThetaEnclosure {
  Jet<Interval> x[3];
};

/// theta_`chart` over `box`, which must lie inside the chart's p-domain.
ThetaEnclosure Enclose(const PouSurface& surface, std::int64_t chart, const ChartBox& box);

}  // namespace invmap::pou
