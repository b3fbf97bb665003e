// The signed-deviation summary of `invmap invert --signed` (scan against a
// CAD solid): how far the points lie outside (+) or inside (-) the part.
#pragma once

#include <cstdint>
#include <cstdio>
#include <limits>
#include <vector>

namespace invmap::cli {

class DeviationSummary {
 public:
  /// `tolerance`: the band +-tolerance whose share the summary reports
  /// (infinity: none).
  explicit DeviationSummary(double tolerance) : tolerance_(tolerance) {}

  /// Adds `count` signed distances (NaN: not found, skipped).
  void Add(const double* signedDistances, std::size_t count);
  /// Prints mean, standard deviation, RMS, extremes, percentiles, the share
  /// inside and outside, and the share within the tolerance band.
  void Print(std::FILE* out) const;

 private:
  static constexpr std::size_t kMaxSamples = 1 << 22;
  double tolerance_;
  std::int64_t count_ = 0, inside_ = 0, outside_ = 0, within_ = 0, below_ = 0;
  double min_ = std::numeric_limits<double>::infinity(), max_ = -std::numeric_limits<double>::infinity();
  double sum_ = 0.0, sum2_ = 0.0;
  std::vector<float> samples_;  // every stride_-th signed distance
  std::int64_t stride_ = 1, seen_ = 0;
};

}  // namespace invmap::cli
