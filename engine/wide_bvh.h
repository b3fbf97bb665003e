// The BVH collapsed to four children per node for the per-point nearest
// search. A binary node visit tests two boxes; a wide node tests its four
// children's boxes at once (their bounds lie side by side, one single
// precision vector per bound), and the tree is half as deep. The binary Bvh
// stays the reference: the wide nodes copy its outward-rounded offsets and
// its leaves, so items keep the Bvh's leaf order (ItemBoxes, SimplexItems).
#pragma once

#include <cstdint>
#include <vector>

#include "engine/bvh_build.h"

namespace invmap::engine {

/// One node: the boxes of up to four children as float offsets from
/// Bvh::Origin() (lo[k][c] .. hi[k][c] for child c), and what each child is.
struct alignas(64) WideNode {
  float lo[3][4];
  float hi[3][4];
  /// Inner child: its node index; leaf child: its first item (Bvh::Items() order).
  std::int32_t first[4];
  /// 0: an inner child; > 0: a leaf of this many items; -1: an unused slot.
  std::int32_t count[4];
};

/// A query point relative to the wide tree, with the slack that keeps box
/// distances computed in single precision below the exact ones.
struct WidePoint {
  float offset[3];  ///< Point minus Bvh::Origin(), rounded to float.
  float slack[3];   ///< Per axis: bound on the rounding of offset and of the gaps.
};

/// Immutable 4-ary tree; node 0 is the root. Safe to read from many threads.
class WideBvh {
 public:
  WideBvh() = default;
  /// Collapses `bvh` (each wide node takes its binary node's grandchildren,
  /// or a child itself where that is a leaf).
  explicit WideBvh(const Bvh& bvh);

  /// The nodes; empty when the Bvh is.
  const std::vector<WideNode>& Nodes() const { return nodes_; }
  /// `p` (ambient coordinates, 3 values; 2D uses p[2] = 0) as a WidePoint.
  WidePoint Prepare(const double* p) const;
  /// Lower bounds of the squared distances from the point to the boxes of
  /// the node's four children (unused slots get +infinity). Never above the
  /// exact squared distance from the point to the child's Bvh::NodeBounds().
  static void ChildDistances2(const WideNode& node, const WidePoint& point, double* distance2);
  /// Heap memory of the nodes, in bytes.
  std::size_t MemoryBytes() const { return nodes_.capacity() * sizeof(WideNode); }

 private:
  std::vector<WideNode> nodes_;
  double origin_[3] = {0, 0, 0};
  /// Largest |offset| of any bound: the scale of their rounding (+infinity
  /// for coordinates beyond the float range, where every bound becomes 0).
  float extent_ = 0.0f;
};

}  // namespace invmap::engine
