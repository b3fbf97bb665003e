// Nearest-cells search over a Bvh: algorithm 3 (lookupCellsNearestToGeometry)
// of the inverse-mapping chapter, with the AABB bounds of section 7.2.1.1.
//
// For a query box Q (a bucket of points, or one point as a flat box) and a
// cell whose bounding box is B, two bounds on distances are used:
//   lower  L(Q, B) = min over q in Q, b in B of |q - b|
//                  = sqrt(sum_k gap_k^2), gap_k = max(0, B.lo_k - Q.hi_k, Q.lo_k - B.hi_k);
//   upper  U(Q, B) = max over q in Q, b in B of |q - b|
//                  = sqrt(sum_k max(Q.hi_k - B.lo_k, B.hi_k - Q.lo_k)^2).
// The cell lies inside B, so for every q in Q its distance to the cell is in
// [L(Q, B), U(Q, B)]; U uses the farthest point of B because the cell may sit
// anywhere inside its box. Both bounds nest: a node's box contains its
// children's boxes, so L can only grow and U only shrink going down the tree.
// Hence, with U* = min over all cells of U(Q, cell box), the cell holding the
// closest point to any q in Q has L(Q, its box) <= U*, and the search returns
// exactly the cells with L <= U*. Node boxes are Bvh::NodeBounds (rounded
// outward); cells use their exact double boxes.
//
// Cost: U* grows with the extent of Q, and the list with it. On 1M random
// cells, one point gets ~33 candidates but an 8-point Morton bucket about two
// cells wide gets ~1000, so a bucket query pays off only when its points
// share most candidates; keep buckets no wider than a cell or two.
#pragma once

#include <limits>
#include <vector>

#include "engine/bvh_build.h"

namespace invmap::engine {

class CellStore;

/// The box of item `i` of `bvh`, a tree over the subdivisions of `store`:
/// the tree's copy, or where it keeps none (BvhBuildOptions::keepItemBoxes)
/// the store's SubdivisionBox, the box the tree was built from.
BvhBox ItemBoxOf(const Bvh& bvh, const CellStore& store, int i);

/// One cell that may hold the closest point of a query.
struct CellCandidate {
  int cell;            ///< Index of the cell's box in the array given to BuildBvh.
  double lowerBound2;  ///< Squared lower bound L(Q, box)^2 (physical length units squared).
};

/// Cells that may hold the closest point of some point of the query box
/// [lo, hi] (physical coordinates; lo == hi for a single point): on return,
/// *out holds exactly the cells whose lower bound L satisfies
/// L^2 <= min(U*^2, maxDistance^2), where U* is the smallest upper bound over
/// all cells (see the file comment), sorted by lowerBound2 and then by cell
/// index. The result depends only on the boxes and the query, not on the
/// tree's shape or on Embree's version; all comparisons use the same
/// double-precision formulas, whose rounding preserves the nesting of bounds.
/// One traversal (algorithm 3): children are visited smaller upper bound
/// first, the smallest upper bound seen so far prunes subtrees, and the
/// leaves' cells collected on the way are trimmed at the end.
/// @param out          output, cleared first; its capacity is reused.
/// @param stackScratch caller-owned traversal stack, cleared first; keep one per
///                     thread and reuse it, so warm calls do not allocate.
/// @param maxDistance  gap tolerance (physical length): cells whose lower bound
///                     exceeds it are dropped; +inf keeps all.
/// Preconditions: lo <= hi on every axis, all finite, maxDistance >= 0; a
/// query that breaks them (e.g. contains NaN) yields an empty list.
/// @param maxCollected stops the search, with *out empty and a false return,
///                     once more cells than this have been collected (the
///                     caller then searches per point); true otherwise.
/// @param store        the store the tree was built over, for a tree without
///                     item boxes (ItemBoxOf); null when it has them.
/// Thread safety: concurrent calls on one Bvh are safe with distinct out and
/// stackScratch.
bool NearestCells(const Bvh& bvh, const double lo[3], const double hi[3],
                  std::vector<CellCandidate>* out, std::vector<int>* stackScratch,
                  double maxDistance = std::numeric_limits<double>::infinity(),
                  std::size_t maxCollected = std::numeric_limits<std::size_t>::max(),
                  const CellStore* store = nullptr);

}  // namespace invmap::engine
