#include "engine/invert_buckets.h"

#include <algorithm>
#include <cmath>

#include "engine/bucket_candidates.h"
#include "engine/bucket_scratch.h"
#include "common/parallel.h"
#include "engine/point_results.h"
#include "engine/point_search.h"
#include "engine/search_bvh.h"
#include "engine/search_candidates.h"
#include "engine/warm_start.h"

namespace invmap::engine {
namespace {

/// Steps of a volume lane's walk through the tetrahedra (as the per-point
/// search's walk).
constexpr int kMaxLaneWalk = 8;

/// The lanes for the bucket's points after `from` (answered `warm`) up to `last`.
void SolveLanesAfter(const SearchIndex& index, const QueryPoints& points, std::int64_t from, std::int64_t last,
                     const WarmStart& warm, bool curveLanes, double maxDistance, BucketScratch& scratch) {
  const CellStore& store = index.cells();
  const double* coord[3] = {points.coord[0] + from, points.coord[1] + from,
                            store.dimension() == 3 ? points.coord[2] + from : nullptr};
  const int count = static_cast<int>(last - from);
  if (curveLanes) {
    SolveBucketInLanes(store, index.wideBvh(), index.bvh(), index.simplices(), coord, count, warm, maxDistance,
                       &scratch.bucketLanes);
  } else {
    SolveInsideByLanes(store, coord, count, warm.cell, kMaxLaneWalk, &scratch.volumeLanes);
  }
}

/// True when the lanes settled point `s` (lane j): its answer is written.
bool WriteSettledLane(const SearchIndex& index, BucketScratch& scratch, bool curveLanes, const double* p, int j,
                      double maxDistance, std::int64_t s, WarmStart* warm, Results* sorted) {
  if (curveLanes ? !scratch.bucketLanes.settled[j] : scratch.volumeLanes.cell[j] < 0) return false;
  const std::int64_t cell = curveLanes ? scratch.bucketLanes.cell[j] : scratch.volumeLanes.cell[j];
  const kernels::CellSolveResult& result = curveLanes ? scratch.bucketLanes.result[j] : scratch.volumeLanes.result[j];
  PointSearch search(index.cells(), index.simplices(), p, scratch, -1, nullptr, maxDistance);
  search.Seed(cell, result);
  search.iterations = curveLanes ? scratch.bucketLanes.iterations[j] : result.iterations;
  WriteFound(index.cells(), search, s, warm, sorted);
  return true;
}

}  // namespace

void InvertBuckets(const SearchIndex& index, const QueryPoints& points, int bucketSize, const InversionOptions& options,
                   Results* sorted) {
  const CellStore& store = index.cells();
  const Bvh& bvh = index.bvh();
  const std::int64_t n = points.count;
  const int dim = store.dimension();
  const double maxDistance = options.maxDistance;
  const bool pointwise = options.pointwise;
  ForEachBlock(
      ExecutionPolicy::Par, (n + bucketSize - 1) / bucketSize, 8,
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
            bool finite = true;
            for (int k = 0; k < dim; ++k) finite = finite && std::isfinite(points.coord[k][s]);
            if (!finite) {
              WriteNotFound(Status::Invalid, s, sorted);
              continue;
            }
            for (int k = 0; k < dim; ++k) {
              const double x = points.coord[k][s];
              blo[k] = haveBox ? std::min(blo[k], x) : x;
              bhi[k] = haveBox ? std::max(bhi[k], x) : x;
            }
            haveBox = true;
          }
          if (!haveBox) continue;
          // Algorithm 3 once for the whole bucket. A volume's points are
          // usually found inside the previous point's cell or a neighbour
          // (TryInsideByWalk) and need no list: there it is built
          // when the first point needs it (the list and the lanes depend on
          // the bucket alone, so when they are built changes no answer).
          bool prepared = false;
          BucketList list;
          const auto prepare = [&] {
            prepared = true;
            list = CullBucket(store, bvh, points, first, last - first, blo, bhi, maxDistance, scratch);
          };
          // Pointwise (InversionOptions::pointwise): no warm start from the
          // previous point and no bucket list or lanes, so that nothing but
          // the point and the geometry decides its search.
          if (!store.hasVolumeCells() && !pointwise) prepare();
          // Curved cells' lanes: once a point of the bucket has an answer
          // on a curved cell, the points after it are solved from that
          // answer a cell at a time (engine/bucket_lanes.h on curves and
          // surfaces, where the affine simplex lanes did not take the
          // bucket; engine/volume_lanes.h for the points inside curved
          // tetrahedra); what they leave goes on point by point. Which point
          // starts them depends on the bucket alone.
          const bool curveLanes = UsesBucketLanes(store, pointwise) && !list.lanesSolved;
          const bool volumeLanes = UsesVolumeLanes(store, pointwise);
          std::int64_t lanesFrom = -1;
          WarmStart warm;
          const bool walks = store.hasVolumeCells() && !store.faceAdjacency().startGrid().empty();
          for (std::int64_t s = first; s < last; ++s) {
            double p[3] = {0, 0, 0};
            bool finite = true;
            for (int k = 0; k < dim; ++k) {
              p[k] = points.coord[k][s];
              finite = finite && std::isfinite(p[k]);
            }
            if (walks) {
              double ahead[2][3];
              for (int a = 0; a < 2; ++a) {
                for (int k = 0; k < 3; ++k) ahead[a][k] = s + 1 + a < last ? points.coord[k][s + 1 + a] : 0.0;
              }
              PrefetchWalk(store, index.simplices(), s + 1 < last ? ahead[0] : nullptr,
                           s + 2 < last ? ahead[1] : nullptr);
            }
            if (!finite) continue;
            const int lane = static_cast<int>(s - lanesFrom);
            if (lanesFrom >= 0 && WriteSettledLane(index, scratch, curveLanes, p, lane, maxDistance, s, &warm, sorted)) {
              continue;
            }
            // A point the curve lanes did not settle goes on from the
            // answer they found in its predicted cell, if any.
            const std::int64_t laneCell = lanesFrom >= 0 && curveLanes ? scratch.bucketLanes.cell[lane] : -1;
            if (pointwise) warm = WarmStart();
            std::int64_t startCell = -1;
            double startRef[3] = {0, 0, 0};
            if (laneCell < 0) PredictStart(store, warm, p, &startCell, startRef);
            PointSearch search(store, index.simplices(), p, scratch, startCell, startRef, maxDistance);
            if (laneCell >= 0) {
              search.Seed(laneCell, scratch.bucketLanes.result[lane]);
              search.iterations = scratch.bucketLanes.iterations[lane];
            }
            if (store.hasVolumeCells()) search.TryInsideByWalk(bvh);
            if (!search.inside) {
              if (!prepared && !pointwise) prepare();
              if (list.use) {
                if (list.lanesSolved) search.Seed(scratch.laneBestCell[s - first], scratch.laneBest[s - first]);
                SearchCandidates(search);
              } else {
                SearchBvh(bvh, index.wideBvh(), index.simplices(), search);
              }
            }
            WriteFound(store, search, s, &warm, sorted);
            // (An affine simplex, known from its BVH item, never starts the
            // volume lanes: its solver, cold in a walk over items, is not read.)
            if (lanesFrom < 0 && (curveLanes ? StartsBucketLanes(store, index.simplices(), warm.cell)
                                             : volumeLanes && index.simplices().item(warm.cell) < 0 &&
                                                   IsLaneTetrahedron(store, warm.cell))) {
              lanesFrom = s;
              SolveLanesAfter(index, points, s, last, warm, curveLanes, maxDistance, scratch);
            }
          }
        }
      },
      options.threads);
}

}  // namespace invmap::engine
