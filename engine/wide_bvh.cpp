#include "engine/wide_bvh.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

#include "common/parallel.h"

namespace invmap::engine {
namespace {

constexpr float kInfF = std::numeric_limits<float>::infinity();

/// Four floats (doubles) in one vector (GCC's vector extension): a wide
/// node's four children at once.
using Float4 = float __attribute__((vector_size(16)));
using Double4 = double __attribute__((vector_size(32)));

/// The four values of a child array (16-byte aligned: WideNode is).
Float4 LoadFloat4(const float* values) {
  Float4 v;
  std::memcpy(&v, values, sizeof(v));
  return v;
}

/// std::max lane by lane: b where a < b, else a (so a NaN in a is kept).
Float4 Max(Float4 a, Float4 b) { return a < b ? b : a; }

/// Offsets beyond this (or beyond the geometry's own extent, when that is
/// larger) are clamped: clamping moves such a point toward every box, which
/// keeps the bound valid, and its float offset then cannot overflow.
constexpr double kClampOffset = 1e30;

/// Relative rounding allowance of the float gaps: a few float epsilons of the
/// operands' magnitude, with a wide margin.
constexpr double kGapRounding = 1.0 / (1 << 20);

/// Puts binary node `node` into slot `slot` of `wide`: its box, and `first`,
/// the wide node it becomes (an inner node) or its first item (a leaf).
void FillSlot(const BvhNode& node, int slot, std::int32_t first, WideNode* wide) {
  for (int k = 0; k < 3; ++k) {
    wide->lo[k][slot] = node.lo[k];
    wide->hi[k][slot] = node.hi[k];
  }
  wide->first[slot] = first;
  wide->count[slot] = node.count;
}

/// Puts `box` into slot `slot` of `wide`.
void SetOrientedBox(const OrientedBox& box, int slot, WideNode* wide) {
  for (int j = 0; j < 3; ++j) {
    for (int k = 0; k < 3; ++k) wide->axis[j][k][slot] = box.axis[j][k];
    wide->orientedLo[j][slot] = box.lo[j];
    wide->orientedHi[j][slot] = box.hi[j];
  }
}

/// A node with every slot unused: empty boxes, unbounded oriented boxes.
WideNode EmptyWideNode() {
  WideNode wide;
  for (int k = 0; k < 3; ++k) {
    for (int c = 0; c < 4; ++c) {
      wide.lo[k][c] = kInfF;
      wide.hi[k][c] = -kInfF;
    }
  }
  for (int c = 0; c < 4; ++c) SetOrientedBox(UnboundedOrientedBox(), c, &wide);
  for (int c = 0; c < 4; ++c) {
    wide.first[c] = 0;
    wide.count[c] = -1;
  }
  return wide;
}

/// The number of wide nodes WideBvh::Collapse makes of the binary `nodes`:
/// the root, and every inner node that fills a slot (an inner child of a
/// wide node's binary node is replaced by its two children).
std::size_t CountWideNodes(const std::vector<BvhNode>& nodes) {
  if (nodes[0].count > 0) return 1;
  std::size_t count = 0;
  std::vector<int> pending = {0};
  while (!pending.empty()) {
    const int binary = pending.back();
    pending.pop_back();
    ++count;
    for (int child = nodes[binary].first; child < nodes[binary].first + 2; ++child) {
      if (nodes[child].count > 0) continue;
      for (int grandchild = nodes[child].first; grandchild < nodes[child].first + 2; ++grandchild) {
        if (nodes[grandchild].count == 0) pending.push_back(grandchild);
      }
    }
  }
  return count;
}

}  // namespace

/// The hull points of every item: copied once in Bvh::Items() order (item
/// i's are the points start[i] .. start[i + 1] of xyz, 3 coordinates each, so
/// the items below a node have theirs side by side; the tree's levels each
/// read them all, and asking `hull` anew at every level took most of the
/// fitting's time), or by index (IndexedHulls).
struct WideBvh::Hulls {
  std::vector<std::size_t> start;
  std::vector<double> xyz;
  IndexedHulls indexed;

  /// The moments of item i's points.
  PointMoments Moments(int i) const {
    if (!indexed.vertices) return PointMoments::Of(xyz.data() + 3 * start[i], start[i + 1] - start[i]);
    double points[3 * 4];
    Gather(i, i + 1, points);
    return PointMoments::Of(points, static_cast<std::size_t>(indexed.perItem));
  }
  /// The points of items [first, end) into `fitter`'s intervals.
  void AddToInterval(int first, int end, OrientedBoxFitter* fitter) const {
    if (!indexed.vertices) {
      fitter->AddToInterval(xyz.data() + 3 * start[first], start[end] - start[first]);
      return;
    }
    // In blocks, so that the fitter sees the points in the order a copy
    // would hold them.
    constexpr int kBlock = 64;
    double points[3 * 4 * kBlock];
    for (int i = first; i < end; i += kBlock) {
      const int stop = std::min(end, i + kBlock);
      Gather(i, stop, points);
      fitter->AddToInterval(points, static_cast<std::size_t>(stop - i) * indexed.perItem);
    }
  }
  /// The points of items [first, end) (indexed) into `out`.
  void Gather(int first, int end, double* out) const {
    const std::int32_t* corner = indexed.corners + static_cast<std::size_t>(indexed.perItem) * first;
    for (std::size_t j = 0; j < static_cast<std::size_t>(end - first) * indexed.perItem; ++j) {
      const double* x = indexed.vertices + 3 * static_cast<std::size_t>(corner[j]);
      out[3 * j] = x[0];
      out[3 * j + 1] = x[1];
      out[3 * j + 2] = x[2];
    }
  }
};

namespace {

WideBvh::Hulls GatherHulls(const Bvh& bvh, const HullPoints& hull) {
  const std::int64_t n = static_cast<std::int64_t>(bvh.Items().size());
  WideBvh::Hulls hulls;
  hulls.start.assign(n + 1, 0);
  ForEachBlock(ExecutionPolicy::Par, n, 1024, [&](std::int64_t begin, std::int64_t stop) {
    std::vector<double> xyz;
    for (std::int64_t i = begin; i < stop; ++i) {
      xyz.clear();
      hull(bvh.Items()[i], &xyz);
      hulls.start[i + 1] = xyz.size() / 3;
    }
  });
  for (std::int64_t i = 0; i < n; ++i) hulls.start[i + 1] += hulls.start[i];
  hulls.xyz.resize(3 * hulls.start[n]);
  ForEachBlock(ExecutionPolicy::Par, n, 1024, [&](std::int64_t begin, std::int64_t stop) {
    std::vector<double> xyz;
    for (std::int64_t i = begin; i < stop; ++i) {
      xyz.clear();
      hull(bvh.Items()[i], &xyz);
      std::copy(xyz.begin(), xyz.end(), hulls.xyz.begin() + 3 * hulls.start[i]);
    }
  });
  return hulls;
}

/// The oriented box along the principal axes of `moments` of the hull
/// points of items [first, end) (Bvh::Items() order), which it reads once
/// more for the intervals.
OrientedBox FitItemsBox(const Bvh& bvh, const WideBvh::Hulls& hulls, int first, int end, int dimension,
                        const PointMoments& moments) {
  if (!moments.complete) return UnboundedOrientedBox();
  OrientedBoxFitter fitter(dimension, bvh.Origin(), moments);
  hulls.AddToInterval(first, end, &fitter);
  return fitter.Result();
}

}  // namespace

WideBvh::WideBvh(const Bvh& bvh, int dimension, const HullPoints& hull, bool itemBoxes) {
  if (itemBoxes) itemOriented_.assign(bvh.Items().size(), UnboundedOrientedBox());
  const std::vector<int> slotBinary = Collapse(bvh);
  if (hull && !nodes_.empty()) FitOrientedBoxes(bvh, dimension, GatherHulls(bvh, hull), slotBinary);
}

WideBvh::WideBvh(const Bvh& bvh, const IndexedHulls& indexed) {
  const std::vector<int> slotBinary = Collapse(bvh);
  Hulls hulls;
  hulls.indexed = indexed;
  if (!nodes_.empty()) FitOrientedBoxes(bvh, 3, hulls, slotBinary);
}

std::vector<int> WideBvh::Collapse(const Bvh& bvh) {
  const std::vector<BvhNode>& nodes = bvh.Nodes();
  if (nodes.empty()) return {};
  std::copy(bvh.Origin(), bvh.Origin() + 3, origin_);
  for (const BvhNode& node : nodes) {
    for (int k = 0; k < 3; ++k) extent_ = std::max({extent_, std::abs(node.lo[k]), std::abs(node.hi[k])});
  }
  // Reserved at their final size: grown by doubling and shrunk, the nodes
  // (71 bytes a triangle) were held twice at the build's peak.
  const std::size_t numWide = CountWideNodes(nodes);
  nodes_.reserve(numWide);
  // (binary inner node, wide node) pairs still to fill with the binary
  // node's grandchildren.
  std::vector<std::pair<int, int>> pending;
  // The binary node of each slot (4 per wide node), -1 for an unused one.
  std::vector<int> slotBinary;
  slotBinary.reserve(4 * numWide);
  slotBinary.assign(4, -1);
  nodes_.push_back(EmptyWideNode());
  if (nodes[0].count > 0) {
    FillSlot(nodes[0], 0, nodes[0].first, &nodes_[0]);
    slotBinary[0] = 0;
    return slotBinary;
  }
  pending.emplace_back(0, 0);
  while (!pending.empty()) {
    const auto [binary, wideIndex] = pending.back();
    pending.pop_back();
    // The children of `binary`, each inner one replaced by its own two
    // children: at most four, leaves where the tree ends earlier.
    int slots[4];
    int used = 0;
    for (int child = nodes[binary].first; child < nodes[binary].first + 2; ++child) {
      if (nodes[child].count > 0) {
        slots[used++] = child;
      } else {
        slots[used++] = nodes[child].first;
        slots[used++] = nodes[child].first + 1;
      }
    }
    for (int s = 0; s < used; ++s) {
      const BvhNode& node = nodes[slots[s]];
      std::int32_t first = node.first;
      if (node.count == 0) {
        first = static_cast<std::int32_t>(nodes_.size());
        nodes_.push_back(EmptyWideNode());
        slotBinary.resize(4 * nodes_.size(), -1);
        pending.emplace_back(slots[s], first);
      }
      FillSlot(node, s, first, &nodes_[wideIndex]);
      slotBinary[4 * wideIndex + s] = slots[s];
    }
  }
  return slotBinary;
}


namespace {

/// Binary nodes this far from the root and nearer split their two subtrees
/// into tasks of their own (up to 2^12 of them).
constexpr int kParallelDepth = 12;

/// Walks the binary tree children first, making each node's moments from
/// its children's (a leaf's from its items, in order) and fitting the
/// oriented box of every node that is a slot of the wide tree as soon as
/// its moments are known. Only the path from the root is held: an array of
/// every node's moments took about 76 bytes a triangle at the build's peak.
/// The moments are merged in the same order whatever the threads, so the
/// boxes are too.
class SlotBoxFitter {
 public:
  SlotBoxFitter(const Bvh& bvh, int dimension, const WideBvh::Hulls& hulls, const std::vector<int>& slotOfBinary,
                const std::vector<PointMoments>& itemMoments, std::vector<WideNode>* wide)
      : bvh_(bvh),
        dimension_(dimension),
        hulls_(hulls),
        slotOfBinary_(slotOfBinary),
        itemMoments_(itemMoments),
        wide_(*wide) {}

  /// The moments of the items below binary node `n` (`depth` below the
  /// root), which are items [*first, *end).
  PointMoments Visit(int n, int depth, int* first, int* end) const {
    const BvhNode& node = bvh_.Nodes()[n];
    PointMoments moments;
    if (node.count > 0) {
      *first = node.first;
      *end = node.first + node.count;
      moments = ItemMoments(node.first);
      for (int item = node.first + 1; item < *end; ++item) {
        moments = PointMoments::Merge(moments, ItemMoments(item));
      }
    } else {
      PointMoments children[2];
      int ends[2];
      const auto visitChildren = [&](std::int64_t begin, std::int64_t stop) {
        for (std::int64_t c = begin; c < stop; ++c) {
          int childFirst;
          children[c] = Visit(node.first + static_cast<int>(c), depth + 1, &childFirst, &ends[c]);
          if (c == 0) *first = childFirst;
        }
      };
      ForEachBlock(depth < kParallelDepth ? ExecutionPolicy::Par : ExecutionPolicy::Seq, 2, 1, visitChildren);
      *end = ends[1];
      moments = PointMoments::Merge(children[0], children[1]);
    }
    if (const int slot = slotOfBinary_[n]; slot >= 0) {
      SetOrientedBox(FitItemsBox(bvh_, hulls_, *first, *end, dimension_, moments), slot % 4, &wide_[slot / 4]);
    }
    return moments;
  }

 private:
  PointMoments ItemMoments(int item) const {
    return itemMoments_.empty() ? hulls_.Moments(item) : itemMoments_[item];
  }

  const Bvh& bvh_;
  int dimension_;
  const WideBvh::Hulls& hulls_;
  const std::vector<int>& slotOfBinary_;
  const std::vector<PointMoments>& itemMoments_;
  std::vector<WideNode>& wide_;
};

}  // namespace

void WideBvh::FitOrientedBoxes(const Bvh& bvh, int dimension, const Hulls& hulls,
                               const std::vector<int>& slotBinary) {
  // With item boxes, each item's moments and box from its own hull points;
  // without, the moments are made where the leaves merge them (not kept:
  // about 110 bytes an item).
  std::vector<PointMoments> itemMoments(itemOriented_.size());
  ForEachBlock(ExecutionPolicy::Par, static_cast<std::int64_t>(itemMoments.size()), 1024,
               [&](std::int64_t begin, std::int64_t stop) {
                 for (std::int64_t i = begin; i < stop; ++i) {
                   const int item = static_cast<int>(i);
                   PointMoments& m = itemMoments[i];
                   m = hulls.Moments(item);
                   if (!m.complete) continue;
                   OrientedBoxFitter fitter(dimension, bvh.Origin(), m);
                   hulls.AddToInterval(item, item + 1, &fitter);
                   itemOriented_[i] = fitter.Result();
                 }
               });
  std::vector<int> slotOfBinary(bvh.Nodes().size(), -1);
  for (std::size_t s = 0; s < slotBinary.size(); ++s) {
    if (slotBinary[s] >= 0) slotOfBinary[slotBinary[s]] = static_cast<int>(s);
  }
  int first, end;
  SlotBoxFitter(bvh, dimension, hulls, slotOfBinary, itemMoments, &nodes_).Visit(0, 0, &first, &end);
}

WidePoint WideBvh::Prepare(const double* p) const {
  WidePoint point;
  for (int k = 0; k < 3; ++k) {
    const double limit = std::max(kClampOffset, static_cast<double>(extent_));
    const double offset = std::clamp(p[k] - origin_[k], -limit, limit);
    point.offset[k] = static_cast<float>(offset);
    // The float offset's own rounding, then that of the float differences
    // with the bounds (and of the double offset), all far below this.
    const double slack = std::abs(offset - static_cast<double>(point.offset[k])) +
                         kGapRounding * (static_cast<double>(extent_) + std::abs(offset));
    // Rounded up, so the float slack is never below the double one.
    point.slack[k] = std::nextafter(static_cast<float>(slack), kInfF);
  }
  // The gap along an oriented box's axis, axis . offset - hi with
  // |axis| < 1 and |hi| within about the extent, rounds by a few float
  // epsilons of the offsets and the extent together (and the offsets' own
  // rounding); each axis's slack holds 16 epsilons of them.
  point.axisSlack = std::nextafter(point.slack[0] + point.slack[1] + point.slack[2], kInfF);
  return point;
}

double WideBvh::OrientedDistance2(const OrientedBox& box, const WidePoint& point) {
  double d2 = 0.0;
  for (int j = 0; j < 3; ++j) {
    const float t =
        box.axis[j][0] * point.offset[0] + box.axis[j][1] * point.offset[1] + box.axis[j][2] * point.offset[2];
    // Written so that NaN (unbounded axes, offsets beyond the float range) gives 0.
    const float shrunk = std::max(box.lo[j] - t, t - box.hi[j]) - point.axisSlack;
    const double gap = shrunk > 0.0f ? shrunk : 0.0f;
    d2 += gap * gap;
  }
  return d2;
}

void WideBvh::ChildDistances2(const WideNode& node, const WidePoint& point, double* box2, double* bound2) {
  // The four children side by side in one vector per bound: the same
  // operations, in the same order, as one child at a time.
  Double4 box = {0, 0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    const Float4 below = LoadFloat4(node.lo[k]) - point.offset[k];
    const Float4 above = point.offset[k] - LoadFloat4(node.hi[k]);
    // Written so that NaN gives 0: with bounds beyond the float range the
    // slack is infinite, and a zero gap is still a valid bound.
    const Float4 shrunk = Max(below, above) - point.slack[k];
    // Squared in double: a gap near the float range would overflow in float.
    const Double4 gap = __builtin_convertvector(shrunk > 0.0f ? shrunk : 0.0f, Double4);
    box += gap * gap;
  }
  Double4 oriented = {0, 0, 0, 0};
  for (int j = 0; j < 3; ++j) {
    const Float4 t = LoadFloat4(node.axis[j][0]) * point.offset[0] + LoadFloat4(node.axis[j][1]) * point.offset[1] +
                     LoadFloat4(node.axis[j][2]) * point.offset[2];
    const Float4 shrunk = Max(LoadFloat4(node.orientedLo[j]) - t, t - LoadFloat4(node.orientedHi[j])) - point.axisSlack;
    const Double4 gap = __builtin_convertvector(shrunk > 0.0f ? shrunk : 0.0f, Double4);
    oriented += gap * gap;
  }
  for (int c = 0; c < 4; ++c) {
    const double unused = node.count[c] < 0 ? std::numeric_limits<double>::infinity() : 0.0;
    box2[c] = std::max(box[c], unused);
    bound2[c] = std::max({box[c], oriented[c], unused});
  }
}

}  // namespace invmap::engine
