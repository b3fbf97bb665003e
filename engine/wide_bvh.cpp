#include "engine/wide_bvh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace invmap::engine {
namespace {

constexpr float kInfF = std::numeric_limits<float>::infinity();

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

/// A node with every slot unused: empty boxes.
WideNode EmptyWideNode() {
  WideNode wide;
  for (int k = 0; k < 3; ++k) {
    for (int c = 0; c < 4; ++c) {
      wide.lo[k][c] = kInfF;
      wide.hi[k][c] = -kInfF;
    }
  }
  for (int c = 0; c < 4; ++c) {
    wide.first[c] = 0;
    wide.count[c] = -1;
  }
  return wide;
}

}  // namespace

WideBvh::WideBvh(const Bvh& bvh) {
  const std::vector<BvhNode>& nodes = bvh.Nodes();
  if (nodes.empty()) return;
  std::copy(bvh.Origin(), bvh.Origin() + 3, origin_);
  for (const BvhNode& node : nodes) {
    for (int k = 0; k < 3; ++k) extent_ = std::max({extent_, std::abs(node.lo[k]), std::abs(node.hi[k])});
  }
  // (binary inner node, wide node) pairs still to fill with the binary
  // node's grandchildren.
  std::vector<std::pair<int, int>> pending;
  nodes_.push_back(EmptyWideNode());
  if (nodes[0].count > 0) {
    FillSlot(nodes[0], 0, nodes[0].first, &nodes_[0]);
    return;
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
        pending.emplace_back(slots[s], first);
      }
      FillSlot(node, s, first, &nodes_[wideIndex]);
    }
  }
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
  return point;
}

void WideBvh::ChildDistances2(const WideNode& node, const WidePoint& point, double* distance2) {
  float gap[3][4];
  for (int k = 0; k < 3; ++k) {
    for (int c = 0; c < 4; ++c) {
      const float outside = std::max(node.lo[k][c] - point.offset[k], point.offset[k] - node.hi[k][c]);
      // Written so that NaN gives 0: with bounds beyond the float range the
      // slack is infinite, and a zero gap is still a valid bound.
      const float shrunk = outside - point.slack[k];
      gap[k][c] = shrunk > 0.0f ? shrunk : 0.0f;
    }
  }
  // Squares in double: a gap near the float range would overflow in float.
  for (int c = 0; c < 4; ++c) {
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) d2 += static_cast<double>(gap[k][c]) * static_cast<double>(gap[k][c]);
    distance2[c] = node.count[c] < 0 ? std::numeric_limits<double>::infinity() : d2;
  }
}

}  // namespace invmap::engine
