#include "engine/nearest_cells.h"

#include <algorithm>
#include <cmath>

#include "engine/cell_store.h"

namespace invmap::engine {

BvhBox ItemBoxOf(const Bvh& bvh, const CellStore& store, int i) {
  if (!bvh.ItemBoxes().empty()) return bvh.ItemBoxes()[i];
  BvhBox box;
  store.SubdivisionBox(bvh.Items()[i], box.lo, box.hi);
  return box;
}

namespace {

/// The query box, copied so the hot loop reads one local object.
struct QueryBox {
  double lo[3];  ///< Lower corner (physical coordinates).
  double hi[3];  ///< Upper corner.
};

/// Squared lower bound L(Q, B)^2: squared distance between the boxes, 0 when
/// they overlap. Monotone in B under rounding: a larger box never gives a
/// larger value, which keeps the pruning exact in floating point.
double LowerBound2(const QueryBox& q, const BvhBox& b) {
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double gap = std::max(0.0, std::max(b.lo[k] - q.hi[k], q.lo[k] - b.hi[k]));
    sum += gap * gap;
  }
  return sum;
}

/// Squared upper bound U(Q, B)^2: squared largest distance between a point of
/// Q and a point of B. Each axis term is >= 0 for non-empty boxes. Monotone
/// in B under rounding: a larger box never gives a smaller value; and never
/// below LowerBound2 of the same boxes.
double UpperBound2(const QueryBox& q, const BvhBox& b) {
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double farthest = std::max(q.hi[k] - b.lo[k], b.hi[k] - q.lo[k]);
    sum += farthest * farthest;
  }
  return sum;
}

/// True when the query box is finite and non-empty on every axis.
bool ValidQuery(const double lo[3], const double hi[3]) {
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(lo[k]) || !std::isfinite(hi[k]) || !(lo[k] <= hi[k])) return false;
  }
  return true;
}

}  // namespace

bool NearestCells(const Bvh& bvh, const double lo[3], const double hi[3],
                  std::vector<CellCandidate>* out, std::vector<int>* stackScratch,
                  double maxDistance, std::size_t maxCollected, const CellStore* store) {
  out->clear();
  stackScratch->clear();
  const std::vector<BvhNode>& nodes = bvh.Nodes();
  if (nodes.empty() || !ValidQuery(lo, hi) || !(maxDistance >= 0.0)) return true;

  const QueryBox query = {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
  const double limit2 = maxDistance * maxDistance;
  const BvhBox* itemBoxes = bvh.ItemBoxes().empty() ? nullptr : bvh.ItemBoxes().data();
  const int* items = bvh.Items().data();
  double bestUpper2 = std::numeric_limits<double>::infinity();

  std::vector<int>& stack = *stackScratch;
  stack.push_back(0);
  while (!stack.empty()) {
    const int index = stack.back();
    stack.pop_back();
    const BvhNode& node = nodes[index];
    // Checked at pop rather than push: the best upper bound may have shrunk
    // while the node waited on the stack.
    if (LowerBound2(query, bvh.NodeBounds(index)) > std::min(bestUpper2, limit2)) continue;

    if (node.count > 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        const BvhBox box = itemBoxes ? itemBoxes[i] : ItemBoxOf(bvh, *store, i);
        bestUpper2 = std::min(bestUpper2, UpperBound2(query, box));
        const double lower2 = LowerBound2(query, box);
        if (lower2 <= std::min(bestUpper2, limit2)) out->push_back({items[i], lower2});
      }
      if (out->size() > maxCollected) {
        out->clear();
        return false;
      }
      continue;
    }

    const int left = node.first;
    const int right = node.first + 1;
    const double upperLeft = UpperBound2(query, bvh.NodeBounds(left));
    const double upperRight = UpperBound2(query, bvh.NodeBounds(right));
    // A child holds at least one cell, and that cell's own upper bound is no
    // larger than the child's, so the child's bound already caps U*. Using it
    // before reaching a leaf prunes earlier without changing the result.
    bestUpper2 = std::min(bestUpper2, std::min(upperLeft, upperRight));
    // Pushed last, popped first: the child with the smaller upper bound is
    // searched first, as in algorithm 3.
    if (upperLeft <= upperRight) {
      stack.push_back(right);
      stack.push_back(left);
    } else {
      stack.push_back(left);
      stack.push_back(right);
    }
  }

  // Cells collected before the bound reached its final value may lie beyond it.
  const double threshold = std::min(bestUpper2, limit2);
  out->erase(std::remove_if(out->begin(), out->end(),
                            [&](const CellCandidate& c) { return c.lowerBound2 > threshold; }),
             out->end());
  std::sort(out->begin(), out->end(), [](const CellCandidate& a, const CellCandidate& b) {
    return a.lowerBound2 < b.lowerBound2 || (a.lowerBound2 == b.lowerBound2 && a.cell < b.cell);
  });
  return true;
}

}  // namespace invmap::engine
