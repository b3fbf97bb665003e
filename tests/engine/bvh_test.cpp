// BVH build (engine/bvh_build.h) and nearest-cells search
// (engine/nearest_cells.h), checked against brute force over all boxes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "engine/bvh_build.h"
#include "engine/nearest_cells.h"

namespace invmap::engine {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Shapes of random box sets, chosen to stress the builder and the bounds.
enum class BoxKind {
  Small,        ///< Small boxes scattered in the unit cube.
  Overlapping,  ///< Large boxes, each overlapping a large share of the others.
  Flat,         ///< Boxes with zero extent on one random axis, and some points.
  Planar,       ///< 2D geometry: z = 0 for every box.
  Identical,    ///< The same box repeated, so no split separates them.
};

/// `n` random boxes of the given kind, reproducible from `seed`.
std::vector<BvhBox> RandomBoxes(int n, BoxKind kind, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<BvhBox> boxes(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    BvhBox& b = boxes[i];
    const double maxSize = kind == BoxKind::Overlapping ? 0.6 : 0.02;
    for (int k = 0; k < 3; ++k) {
      b.lo[k] = unit(rng);
      b.hi[k] = b.lo[k] + maxSize * unit(rng);
    }
    if (kind == BoxKind::Flat) {
      const int axis = static_cast<int>(rng() % 4);  // 3 means: collapse all axes to a point
      for (int k = 0; k < 3; ++k) {
        if (axis == k || axis == 3) b.hi[k] = b.lo[k];
      }
    }
    if (kind == BoxKind::Planar) b.lo[2] = b.hi[2] = 0.0;
    if (kind == BoxKind::Identical) b = {{0.25, 0.5, 0.5}, {0.5, 0.5, 0.75}};
  }
  return boxes;
}

/// Squared distance between boxes, written independently of the library.
double BruteLower2(const double qLo[3], const double qHi[3], const BvhBox& b) {
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    double gap = 0.0;
    if (b.lo[k] > qHi[k]) gap = b.lo[k] - qHi[k];
    if (qLo[k] > b.hi[k]) gap = qLo[k] - b.hi[k];
    sum += gap * gap;
  }
  return sum;
}

/// Squared largest distance between a point of the query and a point of the
/// box (section 7.2.1.1), written independently of the library.
double BruteUpper2(const double qLo[3], const double qHi[3], const BvhBox& b) {
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double far = std::max(std::abs(qHi[k] - b.lo[k]), std::abs(qLo[k] - b.hi[k]));
    sum += far * far;
  }
  return sum;
}

/// The expected answer: every cell with lower bound <= min(U*, maxDistance)
/// (squared), sorted by lower bound then cell index.
std::vector<CellCandidate> BruteNearest(const std::vector<BvhBox>& boxes, const double lo[3],
                                        const double hi[3], double maxDistance) {
  double bestUpper2 = kInf;
  for (const BvhBox& b : boxes) bestUpper2 = std::min(bestUpper2, BruteUpper2(lo, hi, b));
  const double threshold = std::min(bestUpper2, maxDistance * maxDistance);
  std::vector<CellCandidate> expected;
  for (int i = 0; i < static_cast<int>(boxes.size()); ++i) {
    const double lower2 = BruteLower2(lo, hi, boxes[i]);
    if (lower2 <= threshold) expected.push_back({i, lower2});
  }
  std::sort(expected.begin(), expected.end(), [](const CellCandidate& a, const CellCandidate& b) {
    return a.lowerBound2 < b.lowerBound2 || (a.lowerBound2 == b.lowerBound2 && a.cell < b.cell);
  });
  return expected;
}

/// True when `outer` contains `inner`.
bool Contains(const BvhBox& outer, const BvhBox& inner) {
  for (int k = 0; k < 3; ++k) {
    if (!(outer.lo[k] <= inner.lo[k] && inner.hi[k] <= outer.hi[k])) return false;
  }
  return true;
}

/// Checks the layout invariants of a built tree against its input.
void ExpectValidTree(const Bvh& bvh, const std::vector<BvhBox>& boxes, int maxLeafSize) {
  const std::vector<BvhNode>& nodes = bvh.Nodes();
  const int n = static_cast<int>(boxes.size());
  ASSERT_EQ(bvh.NumBoxes(), n);
  ASSERT_EQ(static_cast<int>(bvh.Items().size()), n);
  ASSERT_EQ(static_cast<int>(bvh.ItemBoxes().size()), n);
  if (n == 0) {
    EXPECT_TRUE(nodes.empty());
    return;
  }
  ASSERT_FALSE(nodes.empty());

  std::vector<int> timesInLeaf(n, 0);
  std::vector<int> itemOwners(n, 0);
  std::vector<int> timesReached(nodes.size(), 0);
  std::vector<int> stack = {0};
  while (!stack.empty()) {
    const int index = stack.back();
    stack.pop_back();
    ASSERT_GE(index, 0);
    ASSERT_LT(index, static_cast<int>(nodes.size()));
    ++timesReached[index];
    const BvhNode& node = nodes[index];
    if (node.count > 0) {
      EXPECT_LE(node.count, maxLeafSize) << "leaf " << index;
      ASSERT_GE(node.first, 0);
      ASSERT_LE(node.first + node.count, n);
      for (int i = node.first; i < node.first + node.count; ++i) {
        ++itemOwners[i];
        const int cell = bvh.Items()[i];
        ASSERT_GE(cell, 0);
        ASSERT_LT(cell, n);
        ++timesInLeaf[cell];
        for (int k = 0; k < 3; ++k) {
          EXPECT_EQ(bvh.ItemBoxes()[i].lo[k], boxes[cell].lo[k]);
          EXPECT_EQ(bvh.ItemBoxes()[i].hi[k], boxes[cell].hi[k]);
        }
        EXPECT_TRUE(Contains(bvh.NodeBounds(index), boxes[cell]))
            << "leaf " << index << " item " << cell;
      }
    } else {
      ASSERT_EQ(node.count, 0);
      ASSERT_GT(node.first, index) << "children must follow their parent";
      ASSERT_LT(node.first + 1, static_cast<int>(nodes.size()));
      EXPECT_TRUE(Contains(bvh.NodeBounds(index), bvh.NodeBounds(node.first))) << "node " << index;
      EXPECT_TRUE(Contains(bvh.NodeBounds(index), bvh.NodeBounds(node.first + 1)))
          << "node " << index;
      stack.push_back(node.first);
      stack.push_back(node.first + 1);
    }
  }
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(timesInLeaf[i], 1) << "box " << i;
    EXPECT_EQ(itemOwners[i], 1) << "item slot " << i;
  }
  for (std::size_t i = 0; i < nodes.size(); ++i) EXPECT_EQ(timesReached[i], 1) << "node " << i;

  BvhBox expectedRoot = {{kInf, kInf, kInf}, {-kInf, -kInf, -kInf}};
  for (const BvhBox& b : boxes) {
    for (int k = 0; k < 3; ++k) {
      expectedRoot.lo[k] = std::min(expectedRoot.lo[k], b.lo[k]);
      expectedRoot.hi[k] = std::max(expectedRoot.hi[k], b.hi[k]);
    }
  }
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(bvh.RootBounds().lo[k], expectedRoot.lo[k]);
    EXPECT_EQ(bvh.RootBounds().hi[k], expectedRoot.hi[k]);
  }
  EXPECT_TRUE(Contains(bvh.NodeBounds(0), expectedRoot));
  EXPECT_GE(bvh.MemoryBytes(), nodes.size() * sizeof(BvhNode) + n * (sizeof(int) + sizeof(BvhBox)));
}

/// Compares NearestCells with brute force on random point and box queries,
/// some inside the geometry's bounds, some well outside.
void ExpectSearchMatchesBruteForce(const Bvh& bvh, const std::vector<BvhBox>& boxes,
                                   int numQueries, bool planar, unsigned seed,
                                   double maxDistance = kInf) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> coord(-0.5, 1.5);
  std::uniform_real_distribution<double> size(0.0, 0.1);
  std::vector<CellCandidate> found;
  std::vector<int> stack;
  for (int q = 0; q < numQueries; ++q) {
    double lo[3];
    double hi[3];
    const bool pointQuery = q % 2 == 0;
    for (int k = 0; k < 3; ++k) {
      lo[k] = coord(rng);
      hi[k] = pointQuery ? lo[k] : lo[k] + size(rng);
    }
    if (planar) lo[2] = hi[2] = 0.0;
    NearestCells(bvh, lo, hi, &found, &stack, maxDistance);
    const std::vector<CellCandidate> expected = BruteNearest(boxes, lo, hi, maxDistance);
    SCOPED_TRACE(::testing::Message() << "query " << q << " lo (" << lo[0] << ", " << lo[1]
                                      << ", " << lo[2] << ") hi (" << hi[0] << ", " << hi[1]
                                      << ", " << hi[2] << ")");
    ASSERT_EQ(found.size(), expected.size());
    for (std::size_t i = 0; i < found.size(); ++i) {
      EXPECT_EQ(found[i].cell, expected[i].cell) << "rank " << i;
      EXPECT_EQ(found[i].lowerBound2, expected[i].lowerBound2) << "rank " << i;
    }
    if (maxDistance == kInf && !boxes.empty()) {
      EXPECT_FALSE(found.empty()) << "the cell achieving U* always qualifies";
    }
  }
}

TEST(BvhBuild, NoBoxes) {
  const Bvh bvh = BuildBvh(nullptr, 0);
  ExpectValidTree(bvh, {}, 4);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(bvh.RootBounds().lo[k], kInf);
    EXPECT_EQ(bvh.RootBounds().hi[k], -kInf);
  }
  std::vector<CellCandidate> found = {{7, 1.0}};
  std::vector<int> stack;
  const double p[3] = {0, 0, 0};
  NearestCells(bvh, p, p, &found, &stack);
  EXPECT_TRUE(found.empty());
}

TEST(BvhBuild, OneBox) {
  const std::vector<BvhBox> boxes = {{{1, 2, 3}, {2, 2, 4}}};
  const Bvh bvh = BuildBvh(boxes.data(), 1);
  ExpectValidTree(bvh, boxes, 4);
  ASSERT_EQ(bvh.Nodes().size(), 1u);
  ExpectSearchMatchesBruteForce(bvh, boxes, 50, false, 1);
}

TEST(BvhBuild, TwoBoxes) {
  const std::vector<BvhBox> boxes = {{{0, 0, 0}, {1, 1, 0}}, {{5, 0, 0}, {6, 1, 0}}};
  BvhBuildOptions options;
  options.maxLeafSize = 1;
  const Bvh bvh = BuildBvh(boxes.data(), 2, options);
  ExpectValidTree(bvh, boxes, 1);
  EXPECT_EQ(bvh.Nodes().size(), 3u);
  ExpectSearchMatchesBruteForce(bvh, boxes, 50, true, 2);
}

/// Runs the tree and search checks for one kind of box set.
void CheckKind(BoxKind kind, int n, int maxLeafSize, unsigned seed) {
  const std::vector<BvhBox> boxes = RandomBoxes(n, kind, seed);
  BvhBuildOptions options;
  options.maxLeafSize = maxLeafSize;
  const Bvh bvh = BuildBvh(boxes.data(), n, options);
  ExpectValidTree(bvh, boxes, maxLeafSize);
  ExpectSearchMatchesBruteForce(bvh, boxes, 400, kind == BoxKind::Planar, seed + 100);
}

TEST(BvhBuild, SmallBoxes) { CheckKind(BoxKind::Small, 10000, 4, 11); }
TEST(BvhBuild, OverlappingBoxes) { CheckKind(BoxKind::Overlapping, 10000, 4, 12); }
TEST(BvhBuild, FlatBoxesAndPoints) { CheckKind(BoxKind::Flat, 10000, 2, 13); }
TEST(BvhBuild, PlanarBoxes) { CheckKind(BoxKind::Planar, 10000, 4, 14); }
TEST(BvhBuild, IdenticalBoxes) { CheckKind(BoxKind::Identical, 5000, 4, 15); }
TEST(BvhBuild, LeafSizeOne) { CheckKind(BoxKind::Small, 3000, 1, 16); }
TEST(BvhBuild, LeafSizeLargest) { CheckKind(BoxKind::Small, 3000, 32, 17); }

/// Random point queries near the boxes, compared with brute force by cell
/// and lower bound.
void ExpectPointQueriesMatch(const Bvh& bvh, const std::vector<BvhBox>& boxes, double offset,
                             double scale, unsigned seed) {
  std::vector<CellCandidate> found;
  std::vector<int> stack;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-0.2, 1.2);
  for (int q = 0; q < 200; ++q) {
    double p[3];
    for (double& c : p) c = offset + scale * unit(rng);
    NearestCells(bvh, p, p, &found, &stack);
    const std::vector<CellCandidate> expected = BruteNearest(boxes, p, p, kInf);
    ASSERT_EQ(found.size(), expected.size()) << "query " << q;
    for (std::size_t i = 0; i < found.size(); ++i) {
      EXPECT_EQ(found[i].cell, expected[i].cell);
      EXPECT_EQ(found[i].lowerBound2, expected[i].lowerBound2);
    }
  }
}

TEST(BvhBuild, FarFromOriginKeepsConservativeBounds) {
  // Node offsets are floats: far from the origin one float step is much
  // coarser than the boxes, and near the root's centre one double step of
  // the sum is coarser than many float steps; bounds must stay conservative.
  for (const double offset : {1e7, 1e15}) {
    std::vector<BvhBox> boxes = RandomBoxes(2000, BoxKind::Small, 18);
    for (BvhBox& b : boxes) {
      for (int k = 0; k < 3; ++k) {
        b.lo[k] = offset + 1e-3 * b.lo[k];
        b.hi[k] = offset + 1e-3 * b.hi[k];
      }
    }
    SCOPED_TRACE(::testing::Message() << "offset " << offset);
    const Bvh bvh = BuildBvh(boxes.data(), static_cast<int>(boxes.size()));
    ExpectValidTree(bvh, boxes, 4);
    ExpectPointQueriesMatch(bvh, boxes, offset, 1e-3, 19);
  }
}

TEST(BvhBuild, CoordinatesBeyondFloatRange) {
  // Boxes spread over +-1e300: offsets overflow float and are clamped or
  // rounded to infinity, which must still bound the boxes.
  std::vector<BvhBox> boxes = RandomBoxes(1000, BoxKind::Small, 23);
  for (int i = 0; i < 10; ++i) {
    const double c = (i % 2 == 0 ? 1.0 : -1.0) * std::pow(10.0, 290 + i);
    boxes.push_back({{c, c, 0.5}, {c, 1.5 * c + (c < 0 ? 0.0 : 1.0), 0.5}});
    if (c < 0) std::swap(boxes.back().lo[1], boxes.back().hi[1]);
  }
  const Bvh bvh = BuildBvh(boxes.data(), static_cast<int>(boxes.size()));
  ExpectValidTree(bvh, boxes, 4);
  ExpectPointQueriesMatch(bvh, boxes, 0.0, 1.0, 24);
}

TEST(BvhBuild, SingleThreadBuildGivesSameAnswers) {
  const std::vector<BvhBox> boxes = RandomBoxes(20000, BoxKind::Small, 20);
  BvhBuildOptions oneThread;
  oneThread.maxThreads = 1;
  const Bvh serial = BuildBvh(boxes.data(), static_cast<int>(boxes.size()), oneThread);
  const Bvh parallel = BuildBvh(boxes.data(), static_cast<int>(boxes.size()));
  ExpectValidTree(serial, boxes, 4);
  std::vector<CellCandidate> a;
  std::vector<CellCandidate> b;
  std::vector<int> stack;
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> coord(-0.2, 1.2);
  for (int q = 0; q < 500; ++q) {
    const double p[3] = {coord(rng), coord(rng), coord(rng)};
    NearestCells(serial, p, p, &a, &stack);
    NearestCells(parallel, p, p, &b, &stack);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].cell, b[i].cell);
      EXPECT_EQ(a[i].lowerBound2, b[i].lowerBound2);
    }
  }
}

TEST(BvhBuild, RejectsInvalidInput) {
  std::vector<BvhBox> boxes = RandomBoxes(10, BoxKind::Small, 22);
  boxes[3].lo[1] = std::nan("");
  EXPECT_THROW(BuildBvh(boxes.data(), 10), std::invalid_argument);
  boxes[3] = {{0, 0, 0}, {1, -1, 1}};
  EXPECT_THROW(BuildBvh(boxes.data(), 10), std::invalid_argument);
  boxes[3] = {{0, 0, 0}, {1, kInf, 1}};
  EXPECT_THROW(BuildBvh(boxes.data(), 10), std::invalid_argument);
  boxes[3] = {{0, 0, 0}, {1, 1, 1}};
  EXPECT_THROW(BuildBvh(boxes.data(), -1), std::invalid_argument);
  EXPECT_THROW(BuildBvh(nullptr, 3), std::invalid_argument);
  BvhBuildOptions options;
  options.maxLeafSize = 0;
  EXPECT_THROW(BuildBvh(boxes.data(), 10, options), std::invalid_argument);
  options.maxLeafSize = 33;
  EXPECT_THROW(BuildBvh(boxes.data(), 10, options), std::invalid_argument);
}

TEST(NearestCells, GapToleranceDropsFarCells) {
  const std::vector<BvhBox> boxes = RandomBoxes(10000, BoxKind::Small, 30);
  const Bvh bvh = BuildBvh(boxes.data(), static_cast<int>(boxes.size()));
  for (double maxDistance : {0.0, 0.01, 0.05, 0.3}) {
    SCOPED_TRACE(::testing::Message() << "maxDistance " << maxDistance);
    ExpectSearchMatchesBruteForce(bvh, boxes, 200, false, 31, maxDistance);
  }
}

TEST(NearestCells, PointOnSharedFaceFindsBothCells) {
  // Two unit boxes sharing the face x = 1; a point on that face is at
  // distance 0 from both, and both may hold its closest point.
  const std::vector<BvhBox> boxes = {{{0, 0, 0}, {1, 1, 1}}, {{1, 0, 0}, {2, 1, 1}},
                                     {{5, 5, 5}, {6, 6, 6}}};
  const Bvh bvh = BuildBvh(boxes.data(), 3);
  std::vector<CellCandidate> found;
  std::vector<int> stack;
  const double p[3] = {1.0, 0.5, 0.5};
  NearestCells(bvh, p, p, &found, &stack);
  ASSERT_EQ(found.size(), 2u);
  EXPECT_EQ(found[0].cell, 0);
  EXPECT_EQ(found[1].cell, 1);
  EXPECT_EQ(found[0].lowerBound2, 0.0);
  EXPECT_EQ(found[1].lowerBound2, 0.0);
}

TEST(NearestCells, InvalidQueryGivesEmptyList) {
  const std::vector<BvhBox> boxes = RandomBoxes(100, BoxKind::Small, 40);
  const Bvh bvh = BuildBvh(boxes.data(), 100);
  std::vector<CellCandidate> found;
  std::vector<int> stack;
  const double nanPoint[3] = {0.5, std::nan(""), 0.5};
  NearestCells(bvh, nanPoint, nanPoint, &found, &stack);
  EXPECT_TRUE(found.empty());
  const double lo[3] = {0.5, 0.5, 0.5};
  const double hi[3] = {0.6, 0.4, 0.6};
  NearestCells(bvh, lo, hi, &found, &stack);
  EXPECT_TRUE(found.empty());
  const double infPoint[3] = {kInf, 0.5, 0.5};
  NearestCells(bvh, infPoint, infPoint, &found, &stack);
  EXPECT_TRUE(found.empty());
  NearestCells(bvh, lo, lo, &found, &stack, -1.0);
  EXPECT_TRUE(found.empty());
}

TEST(NearestCells, WarmScratchIsReused) {
  const std::vector<BvhBox> boxes = RandomBoxes(5000, BoxKind::Small, 50);
  const Bvh bvh = BuildBvh(boxes.data(), 5000);
  std::vector<CellCandidate> found;
  std::vector<int> stack;
  const double lo[3] = {0.3, 0.3, 0.3};
  const double hi[3] = {0.4, 0.4, 0.4};
  NearestCells(bvh, lo, hi, &found, &stack);
  const std::vector<CellCandidate> first = found;
  const CellCandidate* foundData = found.data();
  const int* stackData = stack.data();
  NearestCells(bvh, lo, hi, &found, &stack);
  EXPECT_EQ(found.data(), foundData);
  EXPECT_EQ(stack.data(), stackData);
  ASSERT_EQ(found.size(), first.size());
  for (std::size_t i = 0; i < found.size(); ++i) EXPECT_EQ(found[i].cell, first[i].cell);
}

}  // namespace
}  // namespace invmap::engine
