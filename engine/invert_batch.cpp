#include "engine/invert_batch.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "engine/nearest_cells.h"
#include "engine/parallel.h"
#include "engine/spatial_sort.h"

namespace invmap::engine {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Scratch of one task, reused across its buckets so that the per-point path
/// never allocates once warm.
struct BucketScratch {
  std::vector<CellCandidate> candidates;
  std::vector<int> stack;
  std::vector<std::pair<double, int>> order;  // (point's lower bound^2, candidate)
  kernels::SolveWorkspace workspace;
};

double BoxDistance2(const kernels::CellSolver& solver, const double* p, int dim) {
  double d2 = 0.0;
  for (int k = 0; k < dim; ++k) {
    const double d = std::max({solver.boxLo()[k] - p[k], 0.0, p[k] - solver.boxHi()[k]});
    d2 += d * d;
  }
  return d2;
}

void WriteNotFound(Status status, std::int64_t i, Results* results) {
  results->status[i] = status;
  results->patch[i] = -1;
  results->cell[i] = -1;
  for (int k = 0; k < 3; ++k) {
    results->params[3 * i + k] = kNaN;
    results->closest[3 * i + k] = kNaN;
  }
  results->distance[i] = kNaN;
  results->iterations[i] = 0;
}

/// Algorithm 4 for one point over the bucket's candidates: visit cells in
/// order of the point's own lower bound, stop once it reaches the best
/// distance; a volume cell that holds the point ends the search (7.3.2.1).
/// `warmCell`/`warmRef` carry the previous point's answer (warm start).
void InvertPoint(const CellStore& store, const double* p, double maxDistance, BucketScratch& scratch,
                 std::int64_t* warmCell, double* warmRef, std::int64_t index, Results* results) {
  const int dim = store.dimension();
  // The candidates in order of this point's own lower bound, popped lazily
  // from a heap: the search usually stops after the first few.
  std::vector<std::pair<double, int>>& heap = scratch.order;
  heap.clear();
  for (int c = 0; c < static_cast<int>(scratch.candidates.size()); ++c) {
    const std::int64_t cell = scratch.candidates[c].cell;
    heap.emplace_back(BoxDistance2(store.solver(cell), p, dim), c);
  }
  const auto later = [](const std::pair<double, int>& a, const std::pair<double, int>& b) { return a > b; };
  std::make_heap(heap.begin(), heap.end(), later);

  // The gap tolerance is the initial best distance (algorithm 4, line 3).
  double best = maxDistance;
  std::int64_t bestCell = -1;
  kernels::CellSolveResult bestResult;
  int iterations = 0;
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), later);
    const auto [lowerBound2, c] = heap.back();
    heap.pop_back();
    if (lowerBound2 > best * best) break;
    const std::int64_t cell = scratch.candidates[c].cell;
    const kernels::CellSolver& solver = store.solver(cell);
    const kernels::CellSolveResult r =
        solver.Solve(p, cell == *warmCell ? warmRef : nullptr, &scratch.workspace,
                     bestCell >= 0 ? best * best : std::nextafter(best * best, kInf));
    iterations += r.iterations;
    if (r.status == kernels::PointStatus::Farther) continue;
    if (r.distance < best || (bestCell < 0 && r.distance <= best)) {
      best = r.distance;
      bestCell = cell;
      bestResult = r;
    }
    if (solver.isFullRank() && r.status == kernels::PointStatus::Converged && r.distance <= 1e-12 * solver.size()) {
      break;  // inside a volume cell: nothing is closer
    }
  }
  if (bestCell < 0) {
    WriteNotFound(Status::None, index, results);
    results->iterations[index] = iterations;
    return;
  }
  const CellOrigin& origin = store.origin(bestCell);
  const int pd = store.solver(bestCell).cell().shape.paramDim();
  results->status[index] = Status::Found;
  results->patch[index] = origin.patch;
  results->cell[index] = origin.indexInPatch;
  for (int k = 0; k < 3; ++k) {
    results->params[3 * index + k] = k < pd ? origin.paramLo[k] + origin.paramScale[k] * bestResult.ref[k] : kNaN;
    results->closest[3 * index + k] = k < dim ? bestResult.closest[k] : 0.0;
  }
  results->distance[index] = bestResult.distance;
  results->iterations[index] = iterations;
  *warmCell = bestCell;
  std::copy(bestResult.ref, bestResult.ref + 3, warmRef);
}

}  // namespace

void InvertBatch(const CellStore& store, const Bvh& bvh, const QueryPoints& points, const InversionOptions& options,
                 Results* results) {
  const std::int64_t n = points.count;
  const int dim = store.dimension();
  if (n == 0) return;

  // Morton order over the box of the finite points.
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  bool any = false;
  for (std::int64_t i = 0; i < n; ++i) {
    bool finite = true;
    for (int k = 0; k < dim; ++k) finite = finite && std::isfinite(points.coord[k][i]);
    if (!finite) continue;
    for (int k = 0; k < dim; ++k) {
      const double x = points.coord[k][i];
      lo[k] = any ? std::min(lo[k], x) : x;
      hi[k] = any ? std::max(hi[k], x) : x;
    }
    any = true;
  }
  std::vector<std::int64_t> pointNew2Old;
  SpatialSort(ExecutionPolicy::Par, points.coord[0], points.coord[1], dim == 3 ? points.coord[2] : nullptr, n, lo, hi,
              &pointNew2Old, nullptr, options.threads);

  const int bucketSize = std::max(1, options.bucketSize);
  const std::int64_t numBuckets = (n + bucketSize - 1) / bucketSize;
  const double maxDistance = options.maxDistance;
  ForEachBlock(
      ExecutionPolicy::Par, numBuckets, 8,
      [&](std::int64_t bucketBegin, std::int64_t bucketEnd) {
        // One scratch per worker thread, kept across batches: warm calls do
        // not allocate. It holds no state that changes any result.
        thread_local BucketScratch scratch;
        for (std::int64_t b = bucketBegin; b < bucketEnd; ++b) {
          const std::int64_t first = b * bucketSize;
          const std::int64_t last = std::min(n, first + bucketSize);
          // The bucket's box over its finite points; the others are invalid.
          double blo[3] = {0, 0, 0}, bhi[3] = {0, 0, 0};
          bool haveBox = false;
          for (std::int64_t s = first; s < last; ++s) {
            const std::int64_t i = pointNew2Old[s];
            bool finite = true;
            for (int k = 0; k < dim; ++k) finite = finite && std::isfinite(points.coord[k][i]);
            if (!finite) {
              WriteNotFound(Status::Invalid, i, results);
              continue;
            }
            for (int k = 0; k < dim; ++k) {
              const double x = points.coord[k][i];
              blo[k] = haveBox ? std::min(blo[k], x) : x;
              bhi[k] = haveBox ? std::max(bhi[k], x) : x;
            }
            haveBox = true;
          }
          if (!haveBox) continue;
          // Algorithm 3 once for the whole bucket.
          NearestCells(bvh, blo, bhi, &scratch.candidates, &scratch.stack, maxDistance);
          std::int64_t warmCell = -1;
          double warmRef[3] = {0, 0, 0};
          for (std::int64_t s = first; s < last; ++s) {
            const std::int64_t i = pointNew2Old[s];
            double p[3] = {0, 0, 0};
            bool finite = true;
            for (int k = 0; k < dim; ++k) {
              p[k] = points.coord[k][i];
              finite = finite && std::isfinite(p[k]);
            }
            if (!finite) continue;
            InvertPoint(store, p, maxDistance, scratch, &warmCell, warmRef, i, results);
          }
        }
      },
      options.threads);
}

}  // namespace invmap::engine
