// Morton keys and spatial sort (engine/spatial_sort.h), and the blocks and
// sort of common/parallel.h that they rely on for Seq/Par equality.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <mutex>
#include <random>
#include <utility>
#include <vector>

#include "common/parallel.h"
#include "engine/spatial_sort.h"

namespace invmap::engine {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Morton key built bit by bit from the documented definition.
std::uint64_t ReferenceKey(const double lo[3], const double hi[3], const double p[3]) {
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(p[k])) return kNoCode;
  }
  std::uint64_t cell[3];
  for (int k = 0; k < 3; ++k) {
    const double cells = 2097152.0;  // 2^21
    double t = 0.0;
    if (hi[k] > lo[k]) t = (p[k] - lo[k]) * (cells / (hi[k] - lo[k]));
    t = std::floor(t);
    t = std::min(std::max(t, 0.0), cells - 1.0);
    cell[k] = static_cast<std::uint64_t>(t);
  }
  std::uint64_t key = 0;
  for (int bit = 0; bit < 21; ++bit) {
    key |= ((cell[0] >> bit) & 1u) << (3 * bit + 2);
    key |= ((cell[1] >> bit) & 1u) << (3 * bit + 1);
    key |= ((cell[2] >> bit) & 1u) << (3 * bit);
  }
  return key;
}

/// Random SoA points in [-0.2, 1.2]^3 with a share of exact duplicates and of
/// non-finite coordinates.
struct Points {
  std::vector<double> x, y, z;  ///< Coordinates, one entry per point.
};

Points RandomPoints(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> coord(-0.2, 1.2);
  Points pts;
  for (int i = 0; i < n; ++i) {
    double p[3] = {coord(rng), coord(rng), coord(rng)};
    const unsigned roll = static_cast<unsigned>(rng() % 100);
    if (roll < 5 && i > 0) {
      p[0] = pts.x[i / 2];
      p[1] = pts.y[i / 2];
      p[2] = pts.z[i / 2];
    } else if (roll < 8) {
      p[rng() % 3] = (roll == 5) ? kNan : (roll == 6 ? kInf : -kInf);
    }
    pts.x.push_back(p[0]);
    pts.y.push_back(p[1]);
    pts.z.push_back(p[2]);
  }
  return pts;
}

TEST(MortonKey, MatchesBitByBitDefinition) {
  const double lo[3] = {-1.0, 2.0, 0.0};
  const double hi[3] = {3.0, 2.5, 7.0};
  const MortonGrid grid = MakeMortonGrid(lo, hi);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> t(-0.1, 1.1);
  for (int i = 0; i < 20000; ++i) {
    double p[3];
    for (int k = 0; k < 3; ++k) p[k] = lo[k] + t(rng) * (hi[k] - lo[k]);
    EXPECT_EQ(MortonKey(grid, p[0], p[1], p[2]), ReferenceKey(lo, hi, p)) << "point " << i;
  }
  // The corners land in the first and last cells.
  EXPECT_EQ(MortonKey(grid, lo[0], lo[1], lo[2]), 0u);
  EXPECT_EQ(MortonKey(grid, hi[0], hi[1], hi[2]), (std::uint64_t{1} << 63) - 1);
}

TEST(MortonKey, NonFiniteAndCollapsedAxes) {
  const double lo[3] = {0.0, 0.0, 0.0};
  const double hi[3] = {1.0, 1.0, 0.0};  // flat in z: 2D geometry
  const MortonGrid grid = MakeMortonGrid(lo, hi);
  EXPECT_EQ(grid.scale[2], 0.0);
  EXPECT_EQ(MortonKey(grid, kNan, 0.5, 0.0), kNoCode);
  EXPECT_EQ(MortonKey(grid, 0.5, kInf, 0.0), kNoCode);
  EXPECT_EQ(MortonKey(grid, 0.5, 0.5, -kInf), kNoCode);
  const double p[3] = {0.3, 0.7, 123.0};
  EXPECT_EQ(MortonKey(grid, p[0], p[1], p[2]), ReferenceKey(lo, hi, p));
  EXPECT_LT(MortonKey(grid, 1e300, -1e300, 1e300), kNoCode);
  // A non-finite grid box collapses those axes instead of producing NaN.
  const double badLo[3] = {kNan, 0.0, -kInf};
  const double badHi[3] = {1.0, 1.0, 1.0};
  const MortonGrid bad = MakeMortonGrid(badLo, badHi);
  EXPECT_EQ(bad.scale[0], 0.0);
  EXPECT_EQ(bad.scale[2], 0.0);
  EXPECT_LT(MortonKey(bad, 0.5, 0.5, 0.5), kNoCode);
}

/// Checks one sort result against the definition.
void ExpectValidSort(const Points& pts, bool planar, const double lo[3], const double hi[3],
                     const std::vector<std::int64_t>& pointNew2Old,
                     const std::vector<std::uint64_t>& keysNew) {
  const std::int64_t n = static_cast<std::int64_t>(pts.x.size());
  ASSERT_EQ(static_cast<std::int64_t>(pointNew2Old.size()), n);
  ASSERT_EQ(static_cast<std::int64_t>(keysNew.size()), n);
  std::vector<int> seen(static_cast<std::size_t>(n), 0);
  // The sort orders by the key's leading bits; the index takes the rest.
  const std::uint64_t indexMask = (std::uint64_t{1} << SortIndexBits(n)) - 1;
  for (std::int64_t i = 0; i < n; ++i) {
    const std::int64_t old = pointNew2Old[i];
    ASSERT_GE(old, 0);
    ASSERT_LT(old, n);
    ++seen[old];
    const double p[3] = {pts.x[old], pts.y[old], planar ? 0.0 : pts.z[old]};
    EXPECT_EQ(keysNew[i], ReferenceKey(lo, hi, p) & ~indexMask) << "sorted position " << i;
    if (i > 0) {
      EXPECT_LE(keysNew[i - 1], keysNew[i]) << "sorted position " << i;
      if (keysNew[i - 1] == keysNew[i]) {
        EXPECT_LT(pointNew2Old[i - 1], old) << "tie order";
      }
    }
  }
  for (std::int64_t i = 0; i < n; ++i) EXPECT_EQ(seen[i], 1) << "point " << i;

  // Every non-finite point is after every finite one.
  std::int64_t firstInvalid = n;
  for (std::int64_t i = 0; i < n; ++i) {
    const std::int64_t old = pointNew2Old[i];
    const bool finite = std::isfinite(pts.x[old]) && std::isfinite(pts.y[old]) &&
                        (planar || std::isfinite(pts.z[old]));
    if (!finite && firstInvalid == n) firstInvalid = i;
    if (finite) {
      EXPECT_LT(i, firstInvalid) << "finite point after a non-finite one";
    }
  }
}

/// Sorts `pts` (planar: without z) on the box [lo, hi], checks the result
/// against the definition and returns the permutation.
std::vector<std::int64_t> SortAndCheck(const Points& pts, bool planar, const double lo[3], const double hi[3]) {
  std::vector<std::int64_t> pointNew2Old;
  std::vector<std::uint64_t> keysNew;
  SpatialSort(ExecutionPolicy::Par, pts.x.data(), pts.y.data(), planar ? nullptr : pts.z.data(),
              static_cast<std::int64_t>(pts.x.size()), lo, hi, &pointNew2Old, &keysNew);
  ExpectValidSort(pts, planar, lo, hi, pointNew2Old, keysNew);
  return pointNew2Old;
}

TEST(SpatialSort, PermutationSortedWithInvalidLast) {
  const Points pts = RandomPoints(100000, 2);
  const double lo[3] = {0.0, 0.0, 0.0};
  const double hi[3] = {1.0, 1.0, 1.0};
  SortAndCheck(pts, false, lo, hi);
}

TEST(SpatialSort, PlanarPointsWithoutZ) {
  const Points pts = RandomPoints(30000, 3);
  const double lo[3] = {0.0, 0.0, 0.0};
  const double hi[3] = {1.0, 1.0, 0.0};
  SortAndCheck(pts, true, lo, hi);
}

TEST(SpatialSort, IndexBitsHoldEveryIndex) {
  EXPECT_EQ(SortIndexBits(0), 0);
  EXPECT_EQ(SortIndexBits(1), 0);
  EXPECT_EQ(SortIndexBits(2), 1);
  EXPECT_EQ(SortIndexBits(3), 2);
  EXPECT_EQ(SortIndexBits(std::int64_t{1} << 20), 20);
  EXPECT_EQ(SortIndexBits((std::int64_t{1} << 20) + 1), 21);
}

TEST(SpatialSort, TiesInTheLeadingBitsKeepInputOrder) {
  // A cluster a billionth of the box wide: its points share the key's
  // leading bits, so they keep their input order; one point far from the
  // cluster and a NaN show the order across keys still holds.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> offset(0.0, 1e-9);
  Points pts;
  for (int i = 0; i < 5000; ++i) {
    pts.x.push_back(0.25 + offset(rng));
    pts.y.push_back(0.25 + offset(rng));
    pts.z.push_back(0.25 + offset(rng));
  }
  pts.x[10] = 0.1;
  pts.y[20] = kNan;
  const double lo[3] = {0.0, 0.0, 0.0};
  const double hi[3] = {1.0, 1.0, 1.0};
  const std::vector<std::int64_t> pointNew2Old = SortAndCheck(pts, false, lo, hi);
  ASSERT_EQ(pointNew2Old.size(), pts.x.size());
  EXPECT_EQ(pointNew2Old.front(), 10);
  EXPECT_EQ(pointNew2Old.back(), 20);
  EXPECT_EQ(pointNew2Old[1], 0);
  EXPECT_EQ(pointNew2Old[pts.x.size() - 2], static_cast<std::int64_t>(pts.x.size()) - 1);
}

TEST(SpatialSort, SeqAndParAreIdentical) {
  const Points pts = RandomPoints(200000, 4);
  const double lo[3] = {0.0, 0.0, 0.0};
  const double hi[3] = {1.0, 1.0, 1.0};
  const std::int64_t n = static_cast<std::int64_t>(pts.x.size());
  std::vector<std::int64_t> seqNew2Old;
  std::vector<std::uint64_t> seqKeys;
  SpatialSort(ExecutionPolicy::Seq, pts.x.data(), pts.y.data(), pts.z.data(), n, lo, hi,
              &seqNew2Old, &seqKeys);
  for (int threads : {0, 1, 2}) {
    std::vector<std::int64_t> parNew2Old;
    std::vector<std::uint64_t> parKeys;
    SpatialSort(ExecutionPolicy::Par, pts.x.data(), pts.y.data(), pts.z.data(), n, lo, hi,
                &parNew2Old, &parKeys, threads);
    EXPECT_EQ(parNew2Old, seqNew2Old) << "maxThreads " << threads;
    EXPECT_EQ(parKeys, seqKeys) << "maxThreads " << threads;
  }
}

TEST(SpatialSort, TinyInputs) {
  const double lo[3] = {0.0, 0.0, 0.0};
  const double hi[3] = {1.0, 1.0, 1.0};
  std::vector<std::int64_t> pointNew2Old = {5, 6};
  SpatialSort(ExecutionPolicy::Par, nullptr, nullptr, nullptr, 0, lo, hi, &pointNew2Old, nullptr);
  EXPECT_TRUE(pointNew2Old.empty());
  const double x[2] = {kNan, 0.5};
  const double y[2] = {0.5, 0.5};
  SpatialSort(ExecutionPolicy::Par, x, y, nullptr, 1, lo, hi, &pointNew2Old, nullptr);
  EXPECT_EQ(pointNew2Old, std::vector<std::int64_t>({0}));
  SpatialSort(ExecutionPolicy::Seq, x, y, nullptr, 2, lo, hi, &pointNew2Old, nullptr);
  EXPECT_EQ(pointNew2Old, std::vector<std::int64_t>({1, 0}));
}

/// Blocks handed to fn by ForEachBlock, sorted by their start.
std::vector<std::pair<std::int64_t, std::int64_t>> Blocks(ExecutionPolicy policy, std::int64_t n,
                                                          std::int64_t grain, int threads) {
  std::mutex mutex;
  std::vector<std::pair<std::int64_t, std::int64_t>> blocks;
  ForEachBlock(
      policy, n, grain,
      [&](std::int64_t begin, std::int64_t end) {
        std::lock_guard<std::mutex> lock(mutex);
        blocks.emplace_back(begin, end);
      },
      threads);
  std::sort(blocks.begin(), blocks.end());
  return blocks;
}

TEST(Parallel, BlocksCoverRangeAndDoNotDependOnPolicy) {
  for (std::int64_t n : {0, 1, 7, 1000, 12345, 1 << 20}) {
    for (std::int64_t grain : {0, 1, 3, 64, 1000, 5000}) {
      if (n / std::max<std::int64_t>(grain, 1) > 20000) continue;  // keep the test fast
      const auto seq = Blocks(ExecutionPolicy::Seq, n, grain, 0);
      std::int64_t next = 0;
      for (const auto& [begin, end] : seq) {
        EXPECT_EQ(begin, next);
        EXPECT_GT(end, begin);
        EXPECT_LE(end - begin, std::max<std::int64_t>(grain, 1));
        next = end;
      }
      EXPECT_EQ(next, n);
      for (int threads : {0, 1, 2}) {
        EXPECT_EQ(Blocks(ExecutionPolicy::Par, n, grain, threads), seq)
            << "n " << n << " grain " << grain << " threads " << threads;
      }
    }
  }
}

TEST(Parallel, SortWithTotalOrderIsPolicyIndependent) {
  std::mt19937_64 rng(5);
  std::vector<std::pair<int, int>> values(300000);
  for (int i = 0; i < static_cast<int>(values.size()); ++i) {
    values[i] = {static_cast<int>(rng() % 1000), i};
  }
  auto seq = values;
  auto par = values;
  const auto less = [](const std::pair<int, int>& a, const std::pair<int, int>& b) { return a < b; };
  Sort(ExecutionPolicy::Seq, seq.begin(), seq.end(), less);
  Sort(ExecutionPolicy::Par, par.begin(), par.end(), less, 2);
  EXPECT_EQ(seq, par);
  EXPECT_TRUE(std::is_sorted(seq.begin(), seq.end()));
  EXPECT_GE(HardwareThreads(), 1);
}

}  // namespace
}  // namespace invmap::engine
