// The end-of-run summary of `invmap invert` and `invmap trim`, and the
// progress bar shown on a terminal while they run.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "invmap/invmap.h"

namespace invmap::cli {

/// Counts and distance statistics over all chunks of a run.
class RunSummary {
 public:
  /// Adds the results of `count` points.
  void Add(const Results& results, std::size_t count);
  /// Prints points, found/none/invalid, the run's time (`seconds`, of which
  /// `setupSeconds` went to reading the geometry and building its index),
  /// points/s over the rest, and the distance minimum, mean, maximum and
  /// percentiles (from a deterministic sample of at most kMaxSamples found
  /// distances, so memory stays bounded).
  void Print(std::FILE* out, double seconds, double setupSeconds) const;

  std::int64_t points() const { return points_; }

 private:
  static constexpr std::size_t kMaxSamples = 1 << 22;
  std::int64_t points_ = 0, found_ = 0, none_ = 0, invalid_ = 0;
  double minDistance_ = 0.0, maxDistance_ = 0.0, sumDistance_ = 0.0;
  std::vector<float> samples_;  // every stride_-th found distance
  std::int64_t stride_ = 1;
  std::int64_t foundSeen_ = 0;
};

/// A one-line progress bar on stderr: points done, rate and time left (when
/// the total is known). Silent unless stderr is a terminal and not quiet.
class Progress {
 public:
  Progress(bool quiet, std::int64_t total);
  void Update(std::int64_t done);
  /// Clears the bar's line.
  void Done();

 private:
  bool enabled_;
  std::int64_t total_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace invmap::cli
