// Morton (Z-order) keys of query points and the permutation that sorts the
// points by key (docs/how-it-works.md). Points that are close in
// space end up close in the permutation, so a bucket of consecutive sorted
// points has a small bounding box for the nearest-cells search and
// neighbours can warm-start each other.
#pragma once

#include <cstdint>
#include <vector>

#include "common/parallel.h"

namespace invmap::engine {

/// Bits of each coordinate in a Morton key: 3 x 21 = 63 bits.
inline constexpr int kMortonBitsPerAxis = 21;

/// Morton key of a point with a non-finite coordinate. It is larger than
/// every key of a finite point, so such points sort to the end (their
/// results get the status InvalidInput).
inline constexpr std::uint64_t kNoCode = ~std::uint64_t{0};

/// The quantization grid of Morton keys: 2^21 cells per axis spanning a box.
/// Build it with MakeMortonGrid.
struct MortonGrid {
  double lo[3] = {0, 0, 0};     ///< Physical coordinates of the grid's lower corner.
  double scale[3] = {0, 0, 0};  ///< Grid cells per physical length unit; 0 on a collapsed axis.
};

/// Grid that spans the box [lo, hi] (physical coordinates). An axis where the
/// box is empty, flat (hi <= lo) or not finite gets scale 0: every point has
/// grid coordinate 0 on it, which is what 2D input (z = 0) needs.
MortonGrid MakeMortonGrid(const double lo[3], const double hi[3]);

/// Morton key of one point: each coordinate c becomes the integer
/// floor((c - grid.lo) * grid.scale) clamped to [0, 2^21 - 1] (points outside
/// the grid's box are clamped onto it), and the three 21-bit integers are
/// interleaved with x in the most significant position of each 3-bit group:
/// bit 3 * i + 2 = bit i of x, 3 * i + 1 = bit i of y, 3 * i = bit i of z.
/// Returns kNoCode when a coordinate is NaN or infinite.
std::uint64_t MortonKey(const MortonGrid& grid, double x, double y, double z);

/// Bits a sort element gives the input index (the fewest that hold every
/// index below `count`); the Morton key's leading 64 - SortIndexBits(count)
/// bits are what SpatialSort orders by.
int SortIndexBits(std::int64_t count);

/// Sorts `count` points by the leading bits of their Morton key on the grid
/// of the box [lo, hi] (e.g. the geometry's bounds): the key with its low
/// SortIndexBits(count) bits cleared, 44 bits of 63 for a million points,
/// which still tell apart points 1/26000 of the box apart. Returns the
/// permutation that lists the points in that order: pointNew2Old[newIndex] =
/// index of the point in the input arrays. Ties are broken by the input
/// index, so the permutation is unique: Seq and Par, and any thread count,
/// give the same result. Non-finite points have key kNoCode and come last,
/// in input order.
/// @param x, y       coordinates, `count` values each (structure of arrays).
/// @param z          Optional: `count` z coordinates; null for 2D points (z = 0).
/// @param pointNew2Old output, resized to `count`; previous content discarded.
/// @param keysNew    Optional: resized to `count` and filled with the keys sorted
///                   by: keysNew[i] = the key of point pointNew2Old[i] with its
///                   low SortIndexBits(count) bits cleared; null to skip.
/// @param maxThreads Par only: upper limit on threads; 0 = caller's task arena.
/// Memory: two temporary arrays of 8 bytes per point (the radix sort's).
void SpatialSort(ExecutionPolicy policy, const double* x, const double* y, const double* z,
                 std::int64_t count, const double lo[3], const double hi[3],
                 std::vector<std::int64_t>* pointNew2Old, std::vector<std::uint64_t>* keysNew,
                 int maxThreads = 0);

}  // namespace invmap::engine
