// Output of the peer comparison: a Markdown report (the README's table) and a
// CSV with the raw numbers, one row per workload and method.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "bench/peers/harness.h"

namespace invmap::bench {

/// Where and how the run happened.
struct RunInfo {
  std::string date;      ///< UTC, ISO 8601.
  std::string command;   ///< The command line, as typed.
  std::string machine;   ///< CPU model, hardware threads, memory, kernel.
  std::string compiler;  ///< Compiler and build type of the harness.
  double loadStart[3] = {0, 0, 0};  ///< 1, 5 and 15 minute load averages at the start.
  double loadEnd[3] = {0, 0, 0};    ///< The same at the end.
  std::vector<std::string> peersFound;    ///< "OpenCascade 7.6.3", ...
  std::vector<std::string> peersMissing;  ///< With the Debian package to install.
  int allThreads = 1;    ///< Threads of the "all threads" runs.
  /// ParallelCapacity(allThreads) at the start and at the end of the run.
  double capacityStart = 0.0, capacityEnd = 0.0;
  double seconds = 0.0;  ///< Wall time of the whole run.
};

/// invmap on one workload (geometry + point set).
struct InvmapRow {
  std::string workload;     ///< "surface near"
  std::string description;  ///< The geometry and points.
  std::int64_t cells = 0;
  double size = 0.0;        ///< Bounding box diagonal (the tolerances' scale).
  double buildSeconds = 0.0;
  std::int64_t count = 0;
  double seconds1 = 0.0, secondsAll = 0.0;
  std::int64_t threadMismatches = 0;
  std::int64_t notFound = 0;
  double oracleSeconds = 0.0;  ///< One thread, on the same points.
  std::int64_t oracleDisagreements = 0;
};

/// One peer method on one workload, with invmap's rates from the same run.
struct PeerRow {
  std::string workload;
  std::string peer;
  std::string note;
  double setupSeconds = 0.0;
  std::int64_t count = 0;
  double seconds1 = 0.0;
  double secondsAll = -1.0;  ///< < 0: the peer is not thread-safe.
  int threads = 1;
  std::int64_t threadMismatches = 0;
  double invmapRate1 = 0.0, invmapRateAll = 0.0;
  Agreement agreement;
};

/// The Markdown report: run information, invmap's table, the peers' table,
/// workload descriptions and notes.
std::string MarkdownReport(const RunInfo& info, const std::vector<InvmapRow>& invmapRows,
                           const std::vector<PeerRow>& peerRows, const std::vector<std::string>& notes);

/// Writes one CSV row per method and workload (invmap's rows with peer
/// "invmap"); returns false when the file cannot be written.
bool WriteCsv(const std::string& path, const RunInfo& info, const std::vector<InvmapRow>& invmapRows,
              const std::vector<PeerRow>& peerRows);

/// "1.23 M", "45.6 k", "789": points per second for humans.
std::string HumanRate(double rate);

}  // namespace invmap::bench
