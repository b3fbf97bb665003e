// Every tolerance of the solve path, in one place: each number that decides
// whether a slope, a step or a residual is negligible, whether a point lies
// on a face or in a domain, whether two values count as equal, or what
// margin a test keeps over its own rounding; and the budgets of the global
// search. Lengths are relative to the cell's size (the diagonal of its
// control-point box) unless a comment says otherwise; reference coordinates
// live in the unit domains of docs/formats.md, section 1, where a double
// resolves about 1e-16. (Limits of the supported input, such as the largest
// weight, are in kernels/cell_shape.h; heuristics that only steer the order or
// the split of the work, so only its speed, stay with their code.)
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace invmap::kernels {

// ---------------------------------------------------------------- local solve
// (kernels/local_solver.h: the active-set Newton solve of algorithm 5)

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

/// Local solve: the longest Newton step taken without the line search's
/// check, once the decrease it promises is below the rounding of the
/// distance: in the quadratic region such a step leaves an error of about
/// its square (1e-12, far below every other tolerance here), and a longer
/// step promising so little means a nearly singular Hessian, whose model is
/// not trusted. Also how near the last second-order evaluation must be to
/// the answer for its Hessian to stand for the answer's (AnswerModel).
constexpr double kFinalStep = 1e-6;

/// A reference point whose barycentric coordinate is at most this starts the
/// local solve on that face (warm starts on a face, up to rounding).
constexpr double kOnFaceTolerance = 1e-14;

/// A simplex factor whose clamped coordinates sum to more than 1 + this lies
/// farther outside its domain than rounding, and is scaled back onto the
/// face before the last ulps are trimmed (SnapToDomain): about 4500 ulps,
/// beyond what a solve's rounding leaves.
constexpr double kOutsideDomain = 1e-12;

/// Starting points of volume cells guessed from the query (corner
/// barycentrics, nearest control point) are moved this far inside the
/// reference domain (see CellSolver::SolveInside).
constexpr double kStartInset = 1e-2;

/// Full-rank step: the Jacobian is treated as singular below this relative
/// determinant (then the constrained Newton path takes over).
constexpr double kSingularTolerance = 1e-12;

/// Armijo's sufficient decrease: a step is accepted when the squared
/// distance falls by at least this fraction of what its slope promises (the
/// customary value: any decrease short of a vanishing fraction is accepted).
constexpr double kSufficientDecrease = 1e-4;

/// Levenberg-Marquardt fallback of the local solve: the damping added to the
/// Gauss-Newton model's diagonal, relative to its trace plus size^2. Small
/// enough to keep the model's step where the model is well posed, large
/// enough to make a singular one (a collapsed edge, a pole) positive definite.
constexpr double kLevenbergDamping = 1e-10;

/// A local solve for an inside test (LocalSolveOptions::stopAtBoundary)
/// gives up once an iterate on the boundary is still farther than this from
/// the point: a point that far outside the cell is not inside it, and giving
/// up on a point inside only costs the caller a full solve.
constexpr double kBoundaryGiveUp = 1e-6;

// ---------------------------------------------------------------- rounding models

/// Rounding of the map's coordinates, per unit of their magnitude: the
/// evaluation's sums of Bernstein terms carry a few ulps each, 16 ulps
/// covers them. Gives the rounding level of the squared distance below which
/// no decrease can be told (the local solve's line search) and the margin of
/// the tangent-plane lower bound.
constexpr double kMapRounding = 16.0 * std::numeric_limits<double>::epsilon();

/// Rounding of the distance nets' coefficients, per unit of their magnitude
/// squared (DistanceNets::RoundingSlack): their products and subdivisions
/// add a few ulps at each step, 64 ulps covers them.
constexpr double kNetRounding = 64.0 * std::numeric_limits<double>::epsilon();

// ---------------------------------------------------------------- KKT check
// (IsKktPoint: the independent check the global search trusts a local solution by)

/// A slope r . J v counts as stationary below kKktSlope |r| |J v| +
/// kKktSlopeFloor size |J v|: a converged solve leaves slopes near rounding,
/// a point that is not stationary along v has one of the order of |J v| |r|.
/// Looser than the solve's own test (kGradientTolerance) by orders of
/// magnitude, so that a converged solve passes it, and still far below a
/// genuine slope.
constexpr double kKktSlope = 1e-7;
constexpr double kKktSlopeFloor = 1e-12;

/// A coordinate at most this (in reference units) along whose direction the
/// map moves `length` per unit lies on its face when the map there is also
/// within this times the size of the face's: a coordinate of 1e-13 next to a
/// weight of 1e12 is a point of its own, not rounding off the face.
constexpr double kKktOnFace = 1e-12;

// ---------------------------------------------------------------- global search in a cell
// (CellSolver::Search: the certified branch and bound over subdomains)

/// Global search in a cell: a part of the cell is excluded once it cannot
/// hold a point closer than the best one by more than this times size. The
/// distance reported is within this of the true minimum over the cell.
constexpr double kDistanceTolerance = 1e-11;

/// Global search in a cell: a point on a subdomain's boundary still counts as
/// inside it within this (reference coordinates) for the convexity certificate.
constexpr double kInsideTolerance = 1e-9;

/// Tetrahedra: barycentric slack of the test that a point lies beyond the
/// control points' hull, so outside the cell (CellSolver::SolveInside): far
/// above rounding and the distance tolerance relative to the cell's size.
constexpr double kHullSlack = 1e-9;

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

/// Trimmed surfaces: a parameter point within this share of the trimming
/// loops' extent plus magnitude (per parameter) of a loop counts as on it
/// (kernels/trim_region.h): its halvings stop there. Far above the rounding
/// of the halvings, and far below any trimming tolerance a CAD model has.
constexpr double kTrimResolution = 1e-11;

/// Trimmed surfaces: the trimming pieces a cell or subdomain keeps are those
/// near its box widened by this share of its width (plus kTrimResolution of
/// the loops): the subdomains' own boxes are widened by their rounding.
constexpr double kTrimBoxMargin = 1e-9;

/// Pair search (kernels/pair_search.h): the most pairs of subdomains
/// examined for one pair of cells. Each costs more than a cell search's
/// subdomain (two sides' nets, a joint bound); only valleys of equal
/// distances across both cells' parameters (parallel cylinders) come near it.
constexpr int kMaxPairSubdomains = 1024;

/// Pair solve (two cells' joint parameters): a constraint holds when its
/// slack is within this (reference coordinates); points clamped onto a face
/// have slack 0 exactly.
constexpr double kActiveSlack = 1e-14;
/// Pair solve: a QP step shorter than this (reference coordinates) is no step.
constexpr double kNoStep = 1e-15;

// ---------------------------------------------------------------- convexity certificates
// (kernels/curvature_bounds.h, kernels/interval_matrix.h)

/// The range of each second-derivative net coefficient is widened by this
/// times its magnitude: the coefficients carry the rounding of the products
/// that made them (about 1e-16 each), and the widening stays well beyond it.
constexpr double kNetRangeWidening = 1e-12;

/// Rounding of the sums that combine those ranges with the query point,
/// relative to their terms' magnitudes: a few ulps per term, and still far
/// below the ranges' widening.
constexpr double kBoundSumRounding = 1e-14;

/// An interval matrix is proved positive definite only with this margin
/// (relative to its entries, or to 1 for the scaled test) over the rounding
/// of the test's own arithmetic (an eigenvalue solve of a 3 x 3 matrix).
constexpr double kPositivityMargin = 1e-12;

// ---------------------------------------------------------------- affine cells and closed forms
// (7.3.2.2: an affine map needs no Newton iterations)

/// A cell is affine when an affine map reproduces every control point within
/// this times size (IsAffineCell): about 4500 ulps, above the rounding of
/// control points computed by knot insertion or a change of basis, far below
/// the distance tolerance.
constexpr double kAffineCellTolerance = 1e-12;

/// A rational cell counts as polynomial (for the affine test) when every
/// weight equals the first within this, relative to it: about 45 ulps.
constexpr double kEqualWeights = 1e-14;

/// sin^2 of a triangle's angle at its first vertex above which its plane
/// projection alone is trusted when it falls inside the triangle; thinner
/// triangles compare their edges too (see TriangleParameters: the projection
/// loses digits as 1 / sin^2, at most 8 of them above this).
constexpr double kWellShapedSin2 = 1e-8;

/// A tetrahedron whose determinant is at most this times the product of its
/// edge lengths is too flat for Cramer's rule: it is solved face by face.
constexpr double kFlatTetrahedron = 1e-12;

/// Relative volume below which a tetrahedron counts as degenerate for the
/// lane formulas and is left to the scalar solver (which handles collapsed
/// simplices): about 45 ulps of its edges' product.
constexpr double kDegenerateLaneSimplex = 1e-14;

// ---------------------------------------------------------------- thin layers
// (kernels/layer_newton.h: Newton in logarithmic coordinates)

/// Layer Newton has converged when no coordinate changes by more than this,
/// relative to itself (or to kLayerCoordinate when larger): about 450 ulps.
constexpr double kLayerStepTolerance = 1e-13;

/// Layer Newton's first Levenberg-Marquardt damping when the Hessian is not
/// positive definite, relative to its trace (each further attempt ten
/// times larger).
constexpr double kLayerFirstDamping = 1e-12;

// ---------------------------------------------------------------- affine regions
// (engine/affine_regions.h: blocks of B-spline cells sharing one affine map)

/// Cells share a region when their maps agree to this times the patch's
/// size, plus kCoordinateRounding times the largest coordinate: well below
/// the solver's distance tolerance, so a region's answer is the cells'.
constexpr double kAffineRegionTolerance = 1e-12;
/// Rounding of coordinates of large magnitude, relative to it (about 5
/// ulps): cells far from the origin still form regions.
constexpr double kCoordinateRounding = 1e-15;

/// A region's normal equations need a Gram matrix (scaled to a unit
/// diagonal) with determinant above this: nearly parallel directions would
/// lose the face solves' accuracy as 1 / determinant.
constexpr double kRegionConditioning = 1e-8;

/// A region's face minimizer within this (relative to the box's width) of
/// the box is clamped onto it: rounding puts on-face minimizers a hair
/// outside; beyond it the minimizer lies on another face.
constexpr double kRegionFaceSlack = 1e-12;

/// The branch and bound searches' pruning level (of one cell, or of a pair
/// of cells): a part whose squared distance stays at or above it cannot
/// beat a best squared distance `best2` by more than tau (the distance
/// tolerance times the size); `slack` covers the rounding of the nets'
/// coefficients.
inline double ExclusionLevel(double best2, double tau, double slack) {
  // Nothing found yet (a trimmed cell's search may start so): no level.
  if (best2 == std::numeric_limits<double>::infinity()) return best2;
  return best2 - std::max(2.0 * tau * std::sqrt(best2), tau * tau) + slack;
}

}  // namespace invmap::kernels
