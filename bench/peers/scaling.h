// invmap's scaling study: points per second as the geometry grows (cells) and
// as the batch grows (points), written as CSV for plot_scaling.py.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace invmap::bench {

/// Sizes and time caps of the study.
struct ScalingOptions {
  bool quick = false;            ///< Small geometries and batches (a smoke run).
  int allThreads = 0;            ///< Threads of the "all threads" runs (0: all cores).
  int allThreadsCount = 1;       ///< The number that 0 stands for, for the CSV.
  /// A batch is skipped once the previous one of its series took longer than
  /// this divided by its growth factor (so no run exceeds about this).
  double capSeconds = 12.0;
};

/// One measurement.
struct ScalingRow {
  std::string study;     ///< "cells" or "batch".
  std::string geometry;  ///< "surface" (samples::WavySurface) or "trimesh" (samples::BumpySphere).
  std::int64_t cells = 0;
  std::int64_t points = 0;
  int threads = 1;
  double seconds = 0.0;
  double buildSeconds = 0.0;  ///< Manifold::Build of the geometry.
};

/// Runs the study, printing progress on stderr.
std::vector<ScalingRow> RunScaling(const ScalingOptions& options);

/// Writes the rows as CSV; false when the file cannot be written.
bool WriteScalingCsv(const std::string& path, const std::vector<ScalingRow>& rows);

}  // namespace invmap::bench
