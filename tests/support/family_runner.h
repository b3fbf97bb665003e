// One call that runs a whole comparison for the engine tests: build the
// manifold, invert a query set, check every point against a reference and
// log the timings. Header-only: it calls the engine, which the support
// library does not link.
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <initializer_list>
#include <string>

#include "invmap/invmap.h"
#include "tests/support/result_check.h"

namespace invmap::testing {

/// Builds `geometry`, inverts `queries` with `options`, checks every point
/// against `reference` (CheckResults) and reports failures through gtest;
/// prints wall and CPU times of invmap and of the check. Returns the summary.
inline CheckSummary RunFamily(const char* name, const Geometry& geometry, const QuerySet& queries,
                              const ReferenceFn& reference, const InversionOptions& options = {},
                              CheckOptions check = {}) {
  CheckSummary summary;
  const BuildResult built = Manifold::Build(geometry);
  EXPECT_TRUE(built.error.empty()) << name << ": " << built.error;
  if (!built.error.empty()) return summary;
  const double t0 = Seconds(), c0 = CpuSeconds();
  std::string error;
  const Results results = InvertQueries(built.manifold, queries, options, &error);
  const double t1 = Seconds(), c1 = CpuSeconds();
  EXPECT_TRUE(error.empty()) << name << ": " << error;
  if (!error.empty()) return summary;
  check.maxDistance = options.maxDistance;
  summary = CheckResults(geometry, queries, results, reference, check);
  std::printf("[%s] %zu points, %zu cells: invmap %.2f s (cpu %.2f s), reference and checks %.2f s (cpu %.2f s)\n",
              name, queries.size(), built.manifold.Info().cells, t1 - t0, c1 - c0, Seconds() - t1,
              CpuSeconds() - c1);
  std::fflush(stdout);
  EXPECT_EQ(summary.failures, 0) << name << ": " << summary.report;
  return summary;
}

/// Inverts `queries` on 1, 2 and 7 threads for each of `bucketSizes` and
/// expects the same bits from each (CompareBitwise).
inline void ExpectSameBitsOnThreads(const char* name, const Manifold& manifold, const QuerySet& queries,
                                    std::initializer_list<int> bucketSizes) {
  for (int bucketSize : bucketSizes) {
    Results one;
    for (int threads : {1, 2, 7}) {
      InversionOptions options;
      options.threads = threads;
      options.bucketSize = bucketSize;
      std::string error;
      const Results results = InvertQueries(manifold, queries, options, &error);
      ASSERT_TRUE(error.empty()) << name << ": " << error;
      if (threads == 1) {
        one = results;
      } else {
        EXPECT_EQ(CompareBitwise(one, results), "")
            << name << ": threads 1 vs " << threads << ", bucket " << bucketSize;
      }
    }
  }
}

}  // namespace invmap::testing
