// Bounding volume hierarchy over cell bounding boxes (inverse-mapping chapter
// section 7.2). Embree's SAH builder chooses the tree; invmap keeps its own
// flat node array so that its traversal (engine/nearest_cells.h) can query
// with a box of points, which Embree's own queries cannot. Embree stays
// inside bvh_build.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace invmap::engine {

/// Axis-aligned box in physical coordinates: the points p with
/// lo[k] <= p[k] <= hi[k] for k = 0, 1, 2. 2D geometry uses lo[2] = hi[2] = 0.
/// A box with lo == hi on some axes (a flat box, or a point) is valid.
struct BvhBox {
  double lo[3];  ///< Lower corner.
  double hi[3];  ///< Upper corner; hi[k] >= lo[k] for a valid box.
};

/// One node of the flat BVH (binary), 32 bytes. Its bounds are float offsets
/// from Bvh::Origin(), rounded outward so that the box Bvh::NodeBounds()
/// rebuilds from them contains every input box below the node: rounding never
/// shrinks a bound. Floats halve the node array and so the cache misses of
/// the traversal; offsets from the centre keep float resolution relative to
/// the geometry's size, wherever the geometry is.
struct BvhNode {
  float lo[3];         ///< Lower corner minus Bvh::Origin(), rounded down.
  float hi[3];         ///< Upper corner minus Bvh::Origin(), rounded up.
  std::int32_t first;  ///< Inner node: index of the first child; the second child is first + 1.
                       ///< Leaf: index of its first item in Bvh::Items() / ItemBoxes().
  std::int32_t count;  ///< 0 for an inner node; number of items (>= 1) for a leaf.
};

/// Settings of the build.
struct BvhBuildOptions {
  /// Largest number of boxes in one leaf, 1 to 32. Small leaves suit the
  /// nearest-cells search, which tests every item box of a visited leaf.
  int maxLeafSize = 4;
  /// Upper limit on the threads Embree's builder uses; 0 means all cores.
  int maxThreads = 0;
  /// False: the tree keeps no copy of the item boxes (ItemBoxes() is empty),
  /// for a caller that has them elsewhere (a mesh's triangles: 48 bytes
  /// each, ItemBoxOf in engine/nearest_cells.h).
  bool keepItemBoxes = true;
};

/// Immutable BVH over N boxes. Node 0 is the root; children come after
/// their parent in the node array. Items are stored in leaf order: leaf
/// `node` owns items [node.first, node.first + node.count), and every input
/// box index appears in exactly one leaf. Safe to read from many threads.
class Bvh {
 public:
  /// An empty hierarchy (no nodes, no items); the result of building over 0 boxes.
  Bvh() = default;

  /// The nodes; empty when built over 0 boxes, otherwise node 0 is the root.
  const std::vector<BvhNode>& Nodes() const { return nodes_; }
  /// Input box index of each item, in leaf order.
  const std::vector<int>& Items() const { return items_; }
  /// Copy of the input box of each item, in leaf order (ItemBoxes()[i] is
  /// the box of Items()[i]), so a leaf's boxes are contiguous in memory;
  /// empty when built without (BvhBuildOptions::keepItemBoxes).
  const std::vector<BvhBox>& ItemBoxes() const { return itemBoxes_; }
  /// Number of boxes the hierarchy was built over.
  int NumBoxes() const { return static_cast<int>(items_.size()); }
  /// Exact bounds of all boxes; the empty box lo = +inf, hi = -inf when there are none.
  const BvhBox& RootBounds() const { return rootBounds_; }
  /// Point the node offsets are relative to: the centre of RootBounds(), or 0.
  const double* Origin() const { return origin_; }
  /// Bounds of node `index` (0 <= index < Nodes().size()) in physical
  /// coordinates: origin + offset, evaluated in double. They contain every
  /// input box below the node. The build checks its rounding against this
  /// very expression, so callers must use it rather than recompute it.
  BvhBox NodeBounds(int index) const {
    const BvhNode& node = nodes_[index];
    return {{Absolute(origin_[0], node.lo[0]), Absolute(origin_[1], node.lo[1]),
             Absolute(origin_[2], node.lo[2])},
            {Absolute(origin_[0], node.hi[0]), Absolute(origin_[1], node.hi[1]),
             Absolute(origin_[2], node.hi[2])}};
  }
  /// Physical coordinate of a node offset: origin + offset, in double.
  static double Absolute(double origin, float offset) { return origin + static_cast<double>(offset); }
  /// Heap memory held by this object, in bytes (capacity of its arrays).
  std::size_t MemoryBytes() const;

 private:
  friend Bvh BuildBvh(const BvhBox* boxes, int count, const BvhBuildOptions& options);

  std::vector<BvhNode> nodes_;      ///< Flat binary tree, root at 0.
  std::vector<int> items_;          ///< Box index per item, leaf order.
  std::vector<BvhBox> itemBoxes_;   ///< Box per item, leaf order.
  double origin_[3] = {0, 0, 0};    ///< Origin of the node offsets.
  /// Union of all boxes; starts as the empty box.
  BvhBox rootBounds_ = {{kInf, kInf, kInf}, {-kInf, -kInf, -kInf}};

  /// +infinity, the lower corner of the empty box.
  static constexpr double kInf = std::numeric_limits<double>::infinity();
};

/// Builds a BVH over boxes[0 .. count) with Embree's SAH builder
/// (rtcBuildBVH, RTC_BUILD_QUALITY_HIGH, binary nodes). The caller keeps
/// ownership of `boxes`, which may be freed after the call.
/// The tree's shape may depend on Embree's version, but nothing computed from
/// it by NearestCells does.
/// Throws std::invalid_argument if count < 0, a coordinate is not finite,
/// a box has lo > hi, or an option is out of range; throws
/// std::runtime_error with Embree's message if Embree fails (the engine's API
/// boundary catches both). Embree objects are released before returning.
Bvh BuildBvh(const BvhBox* boxes, int count, const BvhBuildOptions& options = {});

}  // namespace invmap::engine
