// The 4-ary collapse of the BVH (engine/wide_bvh.h): every leaf of the binary
// tree is reached exactly once, every child's box is its binary node's box,
// and the single-precision child distances never exceed the exact distances
// to the input boxes below them, wherever the point and the geometry are.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "engine/bvh_build.h"
#include "engine/wide_bvh.h"
#include "tests/engine/wide_tree_items.h"

namespace invmap::engine {
namespace {

/// `n` random boxes of size up to `size` in the cube [offset, offset + 1]^3
/// (z = 0 for planar ones).
std::vector<BvhBox> RandomBoxes(int n, double offset, double size, bool planar, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<BvhBox> boxes(static_cast<std::size_t>(n));
  for (BvhBox& b : boxes) {
    for (int k = 0; k < 3; ++k) {
      b.lo[k] = offset + unit(rng);
      b.hi[k] = b.lo[k] + size * unit(rng);
    }
    if (planar) b.lo[2] = b.hi[2] = 0.0;
  }
  return boxes;
}

/// Squared distance from a point to a box, written independently of the
/// library, in long double: the squares of gaps beyond 1e154 stay finite.
long double ExactDistance2(const BvhBox& b, const double* p) {
  long double sum = 0.0L;
  for (int k = 0; k < 3; ++k) {
    long double gap = 0.0L;
    if (p[k] < b.lo[k]) gap = static_cast<long double>(b.lo[k]) - p[k];
    if (p[k] > b.hi[k]) gap = static_cast<long double>(p[k]) - b.hi[k];
    sum += gap * gap;
  }
  return sum;
}

/// A wide child, as the traversal sees it: a node or a leaf's items.
struct Child {
  int first;
  int count;
};

/// Walks the wide tree: checks the inner children's indices and collects
/// every leaf reached (first item, count).
void CollectLeaves(const WideBvh& wide, int node, std::vector<Child>* leaves) {
  const WideNode& w = wide.Nodes()[node];
  for (int c = 0; c < 4; ++c) {
    if (w.count[c] < 0) continue;
    if (w.count[c] > 0) {
      leaves->push_back({w.first[c], w.count[c]});
      continue;
    }
    ASSERT_GT(w.first[c], node) << "children come after their parent";
    ASSERT_LT(w.first[c], static_cast<int>(wide.Nodes().size()));
    CollectLeaves(wide, w.first[c], leaves);
  }
}

void ExpectLeavesMatchBinary(const Bvh& bvh, const WideBvh& wide) {
  std::vector<Child> binaryLeaves, wideLeaves;
  for (const BvhNode& node : bvh.Nodes()) {
    if (node.count > 0) binaryLeaves.push_back({node.first, node.count});
  }
  CollectLeaves(wide, 0, &wideLeaves);
  const auto byFirst = [](const Child& a, const Child& b) { return a.first < b.first; };
  std::sort(binaryLeaves.begin(), binaryLeaves.end(), byFirst);
  std::sort(wideLeaves.begin(), wideLeaves.end(), byFirst);
  ASSERT_EQ(wideLeaves.size(), binaryLeaves.size());
  for (std::size_t l = 0; l < wideLeaves.size(); ++l) {
    EXPECT_EQ(wideLeaves[l].first, binaryLeaves[l].first);
    EXPECT_EQ(wideLeaves[l].count, binaryLeaves[l].count);
  }
}

/// For random points near and far: each child's distance bound is at most
/// the exact squared distance to every input box below it (and, unless the
/// points are beyond the float range, mostly close to it).
void ExpectConservativeDistances(const Bvh& bvh, const WideBvh& wide, const std::vector<BvhBox>& boxes,
                                 double offset, double spread, unsigned seed) {
  const bool expectTight = spread < 1e38;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-0.5, 1.5);
  int tight = 0, checked = 0;
  for (int q = 0; q < 40; ++q) {
    double p[3];
    for (double& x : p) x = offset + spread * unit(rng);
    // Some points exactly on a box's corner, where the exact distance is 0.
    if (q % 5 == 0) std::copy(boxes[q].lo, boxes[q].lo + 3, p);
    const WidePoint point = wide.Prepare(p);
    for (int node = 0; node < static_cast<int>(wide.Nodes().size()); ++node) {
      double distance2[4], bound2[4];
      WideBvh::ChildDistances2(wide.Nodes()[node], point, distance2, bound2);
      for (int c = 0; c < 4; ++c) {
        std::vector<int> items;
        ItemsBelow(wide, node, c, &items);
        if (items.empty()) {
          EXPECT_EQ(distance2[c], std::numeric_limits<double>::infinity());
          continue;
        }
        long double nearest2 = std::numeric_limits<long double>::infinity();
        for (int i : items) nearest2 = std::min(nearest2, ExactDistance2(bvh.ItemBoxes()[i], p));
        ASSERT_LE(static_cast<long double>(distance2[c]), nearest2) << "node " << node << " child " << c;
        ++checked;
        if (distance2[c] >= 0.5L * nearest2) ++tight;
      }
    }
  }
  // The bound prunes: most are within a factor 2 of the exact distance.
  if (expectTight) {
    EXPECT_GT(tight, checked / 2);
  }
}

TEST(WideBvh, ReachesEveryLeafOnceAndBoundsConservatively) {
  for (const double offset : {0.0, -3.0, 1e7}) {
    for (const bool planar : {false, true}) {
      SCOPED_TRACE(::testing::Message() << "offset " << offset << (planar ? " planar" : ""));
      const std::vector<BvhBox> boxes = RandomBoxes(700, offset, 0.05, planar, 5);
      const Bvh bvh = BuildBvh(boxes.data(), static_cast<int>(boxes.size()));
      const WideBvh wide(bvh);
      ExpectLeavesMatchBinary(bvh, wide);
      ExpectConservativeDistances(bvh, wide, boxes, offset, 1.0, 6);
      // Points far beyond the geometry, up to beyond the float range.
      ExpectConservativeDistances(bvh, wide, boxes, offset, 1e3, 7);
      ExpectConservativeDistances(bvh, wide, boxes, offset, 1e40, 8);
    }
  }
}

TEST(WideBvh, GeometryBeyondTheClampBoundsConservatively) {
  // Boxes of size up to 1e33 spread over 1e35: the geometry reaches past the
  // offset clamp of far points, which must then not move a point past a box.
  std::vector<BvhBox> boxes = RandomBoxes(300, -0.5, 0.01, false, 10);
  for (BvhBox& b : boxes) {
    for (int k = 0; k < 3; ++k) {
      b.lo[k] *= 1e35;
      b.hi[k] *= 1e35;
    }
  }
  const Bvh bvh = BuildBvh(boxes.data(), static_cast<int>(boxes.size()));
  const WideBvh wide(bvh);
  ExpectLeavesMatchBinary(bvh, wide);
  ExpectConservativeDistances(bvh, wide, boxes, 0.0, 1e35, 11);
  ExpectConservativeDistances(bvh, wide, boxes, 0.0, 1e40, 12);
}

TEST(WideBvh, SmallTrees) {
  for (const int n : {1, 2, 3, 5}) {
    const std::vector<BvhBox> boxes = RandomBoxes(n, 0.0, 0.5, false, 9);
    const Bvh bvh = BuildBvh(boxes.data(), n);
    const WideBvh wide(bvh);
    ASSERT_FALSE(wide.Nodes().empty());
    ExpectLeavesMatchBinary(bvh, wide);
  }
  EXPECT_TRUE(WideBvh(BuildBvh(nullptr, 0)).Nodes().empty());
}

}  // namespace
}  // namespace invmap::engine
