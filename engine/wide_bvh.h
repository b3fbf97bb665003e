// The BVH collapsed to four children per node for the per-point nearest
// search. A binary node visit tests two boxes; a wide node tests its four
// children's boxes at once (their bounds lie side by side, one single
// precision vector per bound), and the tree is half as deep. The binary Bvh
// stays the reference: the wide nodes copy its outward-rounded offsets and
// its leaves, so items keep the Bvh's leaf order (ItemBoxes, SimplexItems).
// Given the items' control points, every child and every item also gets an
// oriented box (engine/oriented_box.h), and its lower bound is the larger of
// the two boxes' distances.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "engine/bvh_build.h"
#include "engine/oriented_box.h"

namespace invmap::engine {

/// One node: the boxes of up to four children as float offsets from
/// Bvh::Origin() (lo[k][c] .. hi[k][c] for child c), their oriented boxes
/// (OrientedBox of child c: axis[j][k][c], orientedLo[j][c], orientedHi[j][c]),
/// and what each child is.
struct alignas(64) WideNode {
  float lo[3][4];
  float hi[3][4];
  float axis[3][3][4];
  float orientedLo[3][4];
  float orientedHi[3][4];
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
  float axisSlack;  ///< Bound on the rounding of a gap along an oriented box's axis.
};

/// Appends to `xyz` (3 coordinates per point; 0 as the third in 2D) points
/// whose convex hull holds the geometry of input box `box` (Bvh::Items()
/// values), or nothing when there is none to give (that item and every
/// child above it then get the unbounded oriented box).
using HullPoints = std::function<void(int box, std::vector<double>* xyz)>;

/// Hull points by index, for items that share them (a triangle mesh's
/// vertices): item i (Bvh::Items() order) has the `perItem` (at most 4)
/// points vertices + 3 * corners[perItem * i + j], 3D. Nothing is copied.
struct IndexedHulls {
  const double* vertices = nullptr;
  const std::int32_t* corners = nullptr;
  int perItem = 0;
};

/// Immutable 4-ary tree; node 0 is the root. Safe to read from many threads.
class WideBvh {
 public:
  WideBvh() = default;
  /// Collapses `bvh` (each wide node takes its binary node's grandchildren,
  /// or a child itself where that is a leaf). Without `hull`, every oriented
  /// box is unbounded; with it, each child's is fitted to the hull points of
  /// all items below it, and each item's to its own. `dimension` (2 or 3)
  /// keeps a planar geometry's axes in its plane. Without `itemBoxes` the
  /// items get none (ItemOrientedBox is then unbounded): for a tree whose
  /// items the search solves outright, never testing their boxes (a
  /// triangle mesh's, SimplexItems), they would cost 60 bytes an item.
  explicit WideBvh(const Bvh& bvh, int dimension = 3, const HullPoints& hull = nullptr, bool itemBoxes = true);
  /// The same tree in 3D with hull points by index, and no item boxes: the
  /// same boxes as the constructor above given those points, without the
  /// copy of them it makes (72 bytes a triangle while it builds).
  WideBvh(const Bvh& bvh, const IndexedHulls& hulls);

  /// The nodes; empty when the Bvh is.
  const std::vector<WideNode>& Nodes() const { return nodes_; }
  /// `p` (ambient coordinates, 3 values; 2D uses p[2] = 0) as a WidePoint.
  WidePoint Prepare(const double* p) const;
  /// Lower bounds of the squared distances from the point to the node's
  /// four children (unused slots get +infinity): `box2` to their boxes,
  /// never above the exact squared distance to the child's
  /// Bvh::NodeBounds(); `bound2` the larger of that and the distance to the
  /// child's oriented box, never above the exact squared distance to the
  /// hull of the points of the items below it either.
  static void ChildDistances2(const WideNode& node, const WidePoint& point, double* box2, double* bound2);
  /// Oriented box of item `i` (Bvh::Items() order).
  const OrientedBox& ItemOrientedBox(int i) const {
    return itemOriented_.empty() ? unbounded_ : itemOriented_[i];
  }
  /// Lower bound of the squared distance from the point to the hull of the
  /// points of the item with this oriented box.
  static double OrientedDistance2(const OrientedBox& box, const WidePoint& point);
  /// Heap memory of the nodes and item boxes, in bytes.
  std::size_t MemoryBytes() const {
    return nodes_.capacity() * sizeof(WideNode) + itemOriented_.capacity() * sizeof(OrientedBox);
  }

  /// The hull points of every item while the tree is built (wide_bvh.cpp).
  struct Hulls;

 private:
  /// Copies `bvh`'s nodes into 4-wide ones; returns the binary node of each
  /// slot (4 per wide node), -1 for an unused one.
  std::vector<int> Collapse(const Bvh& bvh);
  /// Fits the oriented boxes of every child and item to the hull points
  /// (see the constructor).
  void FitOrientedBoxes(const Bvh& bvh, int dimension, const Hulls& hulls, const std::vector<int>& slotBinary);

  std::vector<WideNode> nodes_;
  std::vector<OrientedBox> itemOriented_;  ///< empty without item boxes
  OrientedBox unbounded_ = UnboundedOrientedBox();
  double origin_[3] = {0, 0, 0};
  /// Largest |offset| of any bound: the scale of their rounding (+infinity
  /// for coordinates beyond the float range, where every bound becomes 0).
  float extent_ = 0.0f;
};

}  // namespace invmap::engine
