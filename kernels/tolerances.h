// Every tolerance of the solve path, in one place. Lengths are relative to the
// cell's size (the diagonal of its control-point box); reference coordinates
// live in the unit domain of FORMATS.md section 1.
#pragma once

namespace invmap::kernels {

/// Local solve: stop when the slope r . J v along every direction v of the
/// free face is below this times |J v| (size + |r|): the residual's part
/// along the face's image below this times (size + |r|).
constexpr double kGradientTolerance = 1e-14;

/// The stationarity, release and KKT tests judge a direction v of the
/// parameters by |J v|, but never by less than this times size: a direction
/// the map collapses (a pole, a cone's apex) keeps a tolerance, and a cell up
/// to 1e9 times longer than it is thick is judged along its thickness by
/// its thickness.
constexpr double kThinDirection = 1e-9;

/// Local solve: stop when a step moves the reference point by less than this
/// (the unit domain's coordinates are resolved to about 1e-16).
constexpr double kStepTolerance = 1e-15;

/// A reference point whose barycentric coordinate is at most this starts the
/// local solve on that face (warm starts on a face, up to rounding).
constexpr double kOnFaceTolerance = 1e-14;

/// Starting points of volume cells guessed from the query (corner
/// barycentrics, nearest control point) are moved this far inside the
/// reference domain (see CellSolver::SolveInside).
constexpr double kStartInset = 1e-2;

/// Full-rank step: the Jacobian is treated as singular below this relative
/// determinant (then the constrained Newton path takes over).
constexpr double kSingularTolerance = 1e-12;

/// Global search in a cell: a part of the cell is excluded once it cannot
/// hold a point closer than the best one by more than this times size. The
/// distance reported is within this of the true minimum over the cell.
constexpr double kDistanceTolerance = 1e-11;

/// Global search in a cell: a point on a subdomain's boundary still counts as
/// inside it within this (reference coordinates) for the convexity certificate.
constexpr double kInsideTolerance = 1e-9;

/// Global search in a cell: the most subdomains examined for one query, and
/// the deepest bisection. Only near-ties of distinct minima within
/// kDistanceTolerance (and points on an evolute) come near these.
constexpr int kMaxSubdomains = 4096;
/// Global search in a cell: after this many subdomains, each further one also
/// seeds a local solve (see CellSolver::Search).
constexpr int kHardSearch = 64;
/// ... for at most this many subdomains (ties along a whole curve of minima,
/// such as a torus seen from its axis, would otherwise seed thousands).
constexpr int kHardSeeds = 256;
constexpr int kMaxDepth = 64;

/// Pair search (kernels/pair_search.h): the most pairs of subdomains
/// examined for one pair of cells. Each costs more than a cell search's
/// subdomain (two sides' nets, a joint bound); only valleys of equal
/// distances across both cells' parameters (parallel cylinders) come near it.
constexpr int kMaxPairSubdomains = 1024;

}  // namespace invmap::kernels
