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
          WarmStart warm;
          for (std::int64_t s = first; s < last; ++s) {
            double p[3] = {0, 0, 0};
            bool finite = true;
            for (int k = 0; k < dim; ++k) {
              p[k] = points.coord[k][s];
              finite = finite && std::isfinite(p[k]);
            }
            if (!finite) continue;
            if (pointwise) warm = WarmStart();
            std::int64_t startCell;
            double startRef[3];
            PredictStart(store, warm, p, &startCell, startRef);
            PointSearch search(store, index.simplices(), p, scratch, startCell, startRef, maxDistance);
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
          }
        }
      },
      options.threads);
}

}  // namespace invmap::engine
