// Oriented boxes of the wide tree (engine/oriented_box.h): every bound they
// give, of a child or of an item, stays below the exact distance to the
// triangles below it, wherever the point and the geometry are (degenerate
// triangles and planar geometry included); over a finely tessellated tilted
// sheet they are tight where the axis-aligned boxes are not, which is why
// they exist; and the moments merged up the tree are those of the union.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "engine/bvh_build.h"
#include "engine/oriented_box.h"
#include "engine/wide_bvh.h"
#include "tests/engine/wide_tree_items.h"
#include "tests/support/closest_reference.h"

namespace invmap::engine {
namespace {

using invmap::testing::ClosestOnTriangle;

/// Triangles as 9 coordinates each.
using Triangles = std::vector<std::array<double, 9>>;

/// `n` triangles of size up to `size`, randomly oriented, in the cube
/// [offset, offset + 1]^3 (z = 0 when planar); every 50th collapsed to a
/// point and every 50th + 1 to a segment.
Triangles RandomTriangles(int n, double offset, double size, bool planar, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0), signedUnit(-1.0, 1.0);
  Triangles triangles(static_cast<std::size_t>(n));
  for (int t = 0; t < n; ++t) {
    double centre[3];
    for (double& c : centre) c = offset + unit(rng);
    std::array<double, 9>& v = triangles[t];
    for (int corner = 0; corner < 3; ++corner) {
      for (int k = 0; k < 3; ++k) v[3 * corner + k] = centre[k] + size * signedUnit(rng);
    }
    if (t % 50 == 0) std::copy(v.begin(), v.begin() + 3, v.begin() + 3);
    if (t % 50 == 0) std::copy(v.begin(), v.begin() + 3, v.begin() + 6);
    if (t % 50 == 1) {
      for (int k = 0; k < 3; ++k) v[6 + k] = 0.5 * (v[k] + v[3 + k]);
    }
    if (planar) v[2] = v[5] = v[8] = 0.0;
  }
  return triangles;
}

std::vector<BvhBox> TriangleBoxes(const Triangles& triangles) {
  std::vector<BvhBox> boxes(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      boxes[t].lo[k] = std::min({triangles[t][k], triangles[t][3 + k], triangles[t][6 + k]});
      boxes[t].hi[k] = std::max({triangles[t][k], triangles[t][3 + k], triangles[t][6 + k]});
    }
  }
  return boxes;
}

/// The wide tree with the triangles' vertices as hull points.
WideBvh TriangleTree(const Bvh& bvh, const Triangles& triangles, int dimension) {
  return WideBvh(bvh, dimension, [&triangles](int box, std::vector<double>* xyz) {
    xyz->insert(xyz->end(), triangles[box].begin(), triangles[box].end());
  });
}

/// Exact squared distance from p to a triangle (independent closed form).
double ExactDistance2(const std::array<double, 9>& v, const double* p) {
  double s, t, x[3];
  ClosestOnTriangle(p, v.data(), v.data() + 3, v.data() + 6, &s, &t, x);
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) d2 += (p[k] - x[k]) * (p[k] - x[k]);
  return d2;
}

/// For random points: every child's bound and every item's oriented bound is
/// at most the exact squared distance to every triangle below it.
void ExpectConservative(const Bvh& bvh, const WideBvh& wide, const Triangles& triangles, double offset,
                        double spread, bool planar, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-0.5, 1.5);
  for (int q = 0; q < 30; ++q) {
    double p[3];
    for (double& x : p) x = offset + spread * unit(rng);
    // Some points on a triangle's vertex, where the exact distance is 0.
    if (q % 5 == 0) std::copy(triangles[q].begin(), triangles[q].begin() + 3, p);
    if (planar) p[2] = 0.0;
    const WidePoint point = wide.Prepare(p);
    for (int i = 0; i < bvh.NumBoxes(); ++i) {
      ASSERT_LE(WideBvh::OrientedDistance2(wide.ItemOrientedBox(i), point),
                ExactDistance2(triangles[bvh.Items()[i]], p))
          << "item " << i;
    }
    for (int node = 0; node < static_cast<int>(wide.Nodes().size()); ++node) {
      double box2[4], bound2[4];
      WideBvh::ChildDistances2(wide.Nodes()[node], point, box2, bound2);
      for (int c = 0; c < 4; ++c) {
        std::vector<int> items;
        ItemsBelow(wide, node, c, &items);
        if (items.empty()) continue;
        double nearest2 = std::numeric_limits<double>::infinity();
        for (int i : items) nearest2 = std::min(nearest2, ExactDistance2(triangles[bvh.Items()[i]], p));
        ASSERT_LE(bound2[c], nearest2) << "node " << node << " child " << c;
        ASSERT_LE(box2[c], bound2[c]);
      }
    }
  }
}

TEST(OrientedBox, BoundsNeverExceedTheExactDistance) {
  for (const double offset : {0.0, -3.0, 1e7}) {
    for (const bool planar : {false, true}) {
      SCOPED_TRACE(::testing::Message() << "offset " << offset << (planar ? " planar" : ""));
      const Triangles triangles = RandomTriangles(600, offset, 0.05, planar, 21);
      const std::vector<BvhBox> boxes = TriangleBoxes(triangles);
      const Bvh bvh = BuildBvh(boxes.data(), static_cast<int>(boxes.size()));
      const WideBvh wide = TriangleTree(bvh, triangles, planar ? 2 : 3);
      ExpectConservative(bvh, wide, triangles, offset, 1.0, planar, 22);
      ExpectConservative(bvh, wide, triangles, offset, 1e3, planar, 23);
      ExpectConservative(bvh, wide, triangles, offset, 1e40, planar, 24);
    }
  }
}

TEST(OrientedBox, ItemsWithoutHullAreNeverPruned) {
  // A hull callback that gives nothing for every other item: those items and
  // every child above them bound nothing beyond their axis-aligned boxes.
  const Triangles triangles = RandomTriangles(200, 0.0, 0.05, false, 25);
  const std::vector<BvhBox> boxes = TriangleBoxes(triangles);
  const Bvh bvh = BuildBvh(boxes.data(), static_cast<int>(boxes.size()));
  const WideBvh wide(bvh, 3, [&triangles](int box, std::vector<double>* xyz) {
    if (box % 2 == 0) xyz->insert(xyz->end(), triangles[box].begin(), triangles[box].end());
  });
  const double far[3] = {5.0, -4.0, 3.0};
  const WidePoint point = wide.Prepare(far);
  for (int i = 0; i < bvh.NumBoxes(); ++i) {
    if (bvh.Items()[i] % 2 == 1) {
      EXPECT_EQ(WideBvh::OrientedDistance2(wide.ItemOrientedBox(i), point), 0.0);
    }
  }
  double box2[4], bound2[4];
  WideBvh::ChildDistances2(wide.Nodes()[0], point, box2, bound2);
  for (int c = 0; c < 4; ++c) EXPECT_EQ(bound2[c], box2[c]);
}

TEST(OrientedBox, TightOverATiltedSheetWhereBoxesAreNot) {
  // Triangles of size 0.01 on the plane z = 0.6 x + 0.4 y; points 0.005
  // above a triangle's centroid along the normal. The distance is the
  // height; the oriented box of the triangle under the point gives it to
  // within the float slack (about 1e-6 of the geometry's size), its
  // axis-aligned box less than half (the sheet's tilt times the triangle's
  // size exceeds the height: the point is inside the box's z range).
  const double h = 0.01, height = 0.005;
  Triangles triangles;
  for (int i = 0; i < 40; ++i) {
    for (int j = 0; j < 40; ++j) {
      const double x0 = i * h, y0 = j * h;
      const auto z = [](double x, double y) { return 0.6 * x + 0.4 * y; };
      triangles.push_back({x0, y0, z(x0, y0), x0 + h, y0, z(x0 + h, y0), x0, y0 + h, z(x0, y0 + h)});
    }
  }
  const std::vector<BvhBox> boxes = TriangleBoxes(triangles);
  const Bvh bvh = BuildBvh(boxes.data(), static_cast<int>(boxes.size()));
  const WideBvh wide = TriangleTree(bvh, triangles, 3);
  const double norm = std::sqrt(1.0 + 0.36 + 0.16);
  const double normal[3] = {-0.6 / norm, -0.4 / norm, 1.0 / norm};
  int checked = 0;
  for (int i = 0; i < bvh.NumBoxes(); i += 7) {
    const std::array<double, 9>& v = triangles[bvh.Items()[i]];
    double p[3];
    for (int k = 0; k < 3; ++k) p[k] = (v[k] + v[3 + k] + v[6 + k]) / 3.0 + height * normal[k];
    const double exact2 = ExactDistance2(v, p);
    ASSERT_NEAR(exact2, height * height, 1e-15);
    const double oriented2 = WideBvh::OrientedDistance2(wide.ItemOrientedBox(i), wide.Prepare(p));
    EXPECT_GE(oriented2, 0.99 * exact2) << "item " << i;
    double boxGap2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double gap = std::max({bvh.ItemBoxes()[i].lo[k] - p[k], 0.0, p[k] - bvh.ItemBoxes()[i].hi[k]});
      boxGap2 += gap * gap;
    }
    EXPECT_LT(boxGap2, 0.5 * exact2) << "item " << i;
    ++checked;
  }
  EXPECT_GT(checked, 200);
}

TEST(PointMoments, MergedEqualsTheUnion) {
  std::mt19937_64 rng(26);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<double> a(3 * 7), b(3 * 12);
  for (double& x : a) x = 100.0 + unit(rng);
  for (double& x : b) x = 100.5 + 0.1 * unit(rng);
  std::vector<double> both = a;
  both.insert(both.end(), b.begin(), b.end());
  const PointMoments merged = PointMoments::Merge(PointMoments::Of(a.data(), 7), PointMoments::Of(b.data(), 12));
  // The union's moments, directly: mean, then the centred scatter.
  double mean[3] = {0, 0, 0};
  for (int i = 0; i < 19; ++i) {
    for (int k = 0; k < 3; ++k) mean[k] += both[3 * i + k] / 19.0;
  }
  EXPECT_EQ(merged.count, 19.0);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(merged.mean[k], mean[k], 1e-12);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      double s = 0.0;
      for (int i = 0; i < 19; ++i) s += (both[3 * i + r] - mean[r]) * (both[3 * i + c] - mean[c]);
      EXPECT_NEAR(merged.scatter(r, c), s, 1e-11);
    }
  }
  EXPECT_TRUE(merged.complete);
  // No points: no hull, and a union with it has none either.
  const PointMoments missing = PointMoments::Of(nullptr, 0);
  EXPECT_FALSE(missing.complete);
  EXPECT_FALSE(PointMoments::Merge(merged, missing).complete);
}

}  // namespace
}  // namespace invmap::engine
