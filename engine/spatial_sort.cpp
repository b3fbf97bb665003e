#include "engine/spatial_sort.h"

#include <algorithm>
#include <cmath>
#include <memory>

namespace invmap::engine {
namespace {

/// Largest grid coordinate on one axis, 2^21 - 1, as a double for clamping.
constexpr double kMaxGridCoord = static_cast<double>((std::uint64_t{1} << kMortonBitsPerAxis) - 1);

/// Points per block of the key loop: large enough to hide task overhead,
/// small enough to balance 2 to 64 threads on a million points.
constexpr std::int64_t kKeyGrain = 16384;

/// Spreads the low 21 bits of v so that bit i moves to bit 3 * i.
std::uint64_t SpreadBits3(std::uint64_t v) {
  v &= 0x1fffffULL;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

/// Grid coordinate of c on one axis; c is finite.
std::uint64_t GridCoord(double c, double lo, double scale) {
  // A collapsed axis has lo = 0 and scale = 0, and c - lo cannot overflow for
  // finite c, so t is never 0 * inf = NaN; an overflow on a real axis gives
  // +-inf, which the clamp handles.
  const double t = (c - lo) * scale;
  return static_cast<std::uint64_t>(std::min(std::max(t, 0.0), kMaxGridCoord));
}

/// Points per block of the radix sort's count and scatter passes.
constexpr std::int64_t kRadixBlock = 65536;
constexpr int kDigitBits = 8;
constexpr int kDigits = 1 << kDigitBits;

/// Sorts `order` (sort elements: the key's leading bits above `indexBits`,
/// the input index below) by value: a least significant digit radix sort
/// over the key's bits only, 8 a pass, passes where every element has the
/// same digit skipped. The elements start in index order and every pass is
/// stable, so the index bits need no pass of their own. Each pass counts
/// digits per block of points, turns the counts into offsets in (digit,
/// block) order and moves every block's points to their places in parallel;
/// the blocks are fixed, so the result is the same for any thread count.
void RadixSortByKey(ExecutionPolicy policy, std::uint64_t* order, std::int64_t count, int indexBits,
                    int maxThreads) {
  const std::int64_t numBlocks = (count + kRadixBlock - 1) / kRadixBlock;
  // Not zero-filled: the first pass writes it, in parallel.
  const std::unique_ptr<std::uint64_t[]> buffer(new std::uint64_t[static_cast<std::size_t>(count)]);
  std::vector<std::int64_t> offsets(static_cast<std::size_t>(numBlocks) * kDigits);
  std::uint64_t* from = order;
  std::uint64_t* to = buffer.get();
  for (int shift = indexBits; shift < 64; shift += kDigitBits) {
    const auto digit = [shift](std::uint64_t element) { return static_cast<int>((element >> shift) & (kDigits - 1)); };
    ForEachBlock(
        policy, numBlocks, 1,
        [&](std::int64_t firstBlock, std::int64_t endBlock) {
          for (std::int64_t b = firstBlock; b < endBlock; ++b) {
            std::int64_t* row = offsets.data() + b * kDigits;
            std::fill(row, row + kDigits, 0);
            for (std::int64_t i = b * kRadixBlock; i < std::min(count, (b + 1) * kRadixBlock); ++i) {
              ++row[digit(from[i])];
            }
          }
        },
        maxThreads);
    std::int64_t next = 0;
    bool oneDigit = false;
    for (int d = 0; d < kDigits && !oneDigit; ++d) {
      std::int64_t total = 0;
      for (std::int64_t b = 0; b < numBlocks; ++b) total += offsets[b * kDigits + d];
      oneDigit = total == count;
      for (std::int64_t b = 0; b < numBlocks; ++b) {
        const std::int64_t c = offsets[b * kDigits + d];
        offsets[b * kDigits + d] = next;
        next += c;
      }
    }
    if (oneDigit) continue;  // every key has this digit: the order stands
    ForEachBlock(
        policy, numBlocks, 1,
        [&](std::int64_t firstBlock, std::int64_t endBlock) {
          for (std::int64_t b = firstBlock; b < endBlock; ++b) {
            std::int64_t* row = offsets.data() + b * kDigits;
            for (std::int64_t i = b * kRadixBlock; i < std::min(count, (b + 1) * kRadixBlock); ++i) {
              to[row[digit(from[i])]++] = from[i];
            }
          }
        },
        maxThreads);
    std::swap(from, to);
  }
  if (from != order) std::copy(from, from + count, order);
}

}  // namespace

MortonGrid MakeMortonGrid(const double lo[3], const double hi[3]) {
  MortonGrid grid;
  for (int k = 0; k < 3; ++k) {
    // The grid divides [lo, hi] into 2^21 cells, so the point at hi lands in
    // cell 2^21, which the clamp in GridCoord folds into the last cell.
    const double scale = std::ldexp(1.0, kMortonBitsPerAxis) / (hi[k] - lo[k]);
    if (std::isfinite(lo[k]) && std::isfinite(hi[k]) && hi[k] > lo[k] && std::isfinite(scale)) {
      grid.lo[k] = lo[k];
      grid.scale[k] = scale;
    }
  }
  return grid;
}

std::uint64_t MortonKey(const MortonGrid& grid, double x, double y, double z) {
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) return kNoCode;
  return SpreadBits3(GridCoord(x, grid.lo[0], grid.scale[0])) << 2 |
         SpreadBits3(GridCoord(y, grid.lo[1], grid.scale[1])) << 1 |
         SpreadBits3(GridCoord(z, grid.lo[2], grid.scale[2]));
}

int SortIndexBits(std::int64_t count) {
  int bits = 0;
  while (bits < 63 && (std::int64_t{1} << bits) < count) ++bits;
  return bits;
}

void SpatialSort(ExecutionPolicy policy, const double* x, const double* y, const double* z,
                 std::int64_t count, const double lo[3], const double hi[3],
                 std::vector<std::int64_t>* pointNew2Old, std::vector<std::uint64_t>* keysNew,
                 int maxThreads) {
  count = std::max<std::int64_t>(count, 0);
  const MortonGrid grid = MakeMortonGrid(lo, hi);
  // One 64-bit word a point, the key's leading bits over the input index: a
  // third of the memory traffic of a (key, index) pair sorted on all 63 key
  // bits, and 44 leading bits (for a million points) still tell apart
  // points 1/26000 of the box apart, finer than any bucket.
  const int indexBits = SortIndexBits(count);
  const std::uint64_t indexMask = (std::uint64_t{1} << indexBits) - 1;
  // Not zero-filled: the key loop writes every entry, in parallel.
  const std::unique_ptr<std::uint64_t[]> order(new std::uint64_t[static_cast<std::size_t>(count)]);
  ForEachBlock(
      policy, count, kKeyGrain,
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t i = begin; i < end; ++i) {
          const std::uint64_t key = MortonKey(grid, x[i], y[i], z != nullptr ? z[i] : 0.0);
          order[i] = (key & ~indexMask) | static_cast<std::uint64_t>(i);
        }
      },
      maxThreads);
  RadixSortByKey(policy, order.get(), count, indexBits, maxThreads);

  pointNew2Old->resize(static_cast<std::size_t>(count));
  if (keysNew != nullptr) keysNew->resize(static_cast<std::size_t>(count));
  ForEachBlock(
      policy, count, kKeyGrain,
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t i = begin; i < end; ++i) {
          (*pointNew2Old)[i] = static_cast<std::int64_t>(order[i] & indexMask);
          if (keysNew != nullptr) (*keysNew)[i] = order[i] & ~indexMask;
        }
      },
      maxThreads);
}

}  // namespace invmap::engine
