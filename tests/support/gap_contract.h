// The gap tolerance's contract (docs/cli.md, "Gap tolerance") checked on a
// built manifold: a point within D of the geometry is found, D = 0
// included; one farther is none.
#pragma once

#include <vector>

#include "invmap/invmap.h"

namespace invmap::testing {

/// Inverts `queries` (3 coordinates per point) without a limit, then their
/// reported closest points (on the geometry to rounding) with a gap
/// tolerance of 0: every one must be found, within the solve's tolerance
/// (1e-11 of `size`) of the geometry, as it is without a limit. The queries
/// themselves, those at least 1e-9 of `size` away, must then be none with a
/// gap tolerance of 0. Failures are reported with the first such point.
void ExpectClosestPointsFoundAtZeroGap(const Manifold& manifold, const std::vector<double>& queries, double size);

}  // namespace invmap::testing
