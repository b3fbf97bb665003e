// Timing, threading and agreement of the peer comparison: runs invmap and a
// peer on the same points and measures points per second and who is right.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "bench/peers/peer.h"
#include "bench/peers/workloads.h"
#include "invmap/invmap.h"

namespace invmap::bench {

/// Wall-clock seconds from a steady clock.
double Now();

/// Runs fn(thread, begin, end) over [0, n) on `threads` threads (thread 0 is
/// the caller), handing out chunks of `chunk` indices from a shared counter so
/// that a slow chunk does not leave the other threads idle.
void ParallelChunks(int threads, std::int64_t n, std::int64_t chunk,
                    const std::function<void(int, std::int64_t, std::int64_t)>& fn);

/// Speed-up of a CPU-bound loop on `threads` threads over the same loop on 1
/// thread, measured now (about half a second): what the machine can give this
/// process at the moment. `threads` on an idle machine; less when other work
/// competes for the cores, which caps every threaded rate of the run too.
double ParallelCapacity(int threads);

/// invmap on one point set.
struct InvmapRun {
  std::int64_t count = 0;        ///< Points inverted (a prefix of the set).
  double seconds1 = 0.0;         ///< InversionOptions::threads = 1.
  double secondsAll = 0.0;       ///< InversionOptions::threads = allThreads (0: all cores).
  Results results;               ///< From the 1-thread run.
  std::int64_t threadMismatches = 0;  ///< Points whose answer differs between the two runs.
  std::int64_t notFound = 0;     ///< Points with a status other than Found.
};

/// Times invmap on the first points of `set`: a warm-up, a calibration that
/// caps the count at what fits in `budgetSeconds` (never below
/// min(maxCount, 10^5)), then one timed run with 1 thread and one with
/// `allThreads` (0 = all cores).
InvmapRun RunInvmap(const Manifold& manifold, const PointSet& set, std::int64_t maxCount, double budgetSeconds,
                    int allThreads);

/// A peer method on one point set.
struct PeerRun {
  /// Creating the first worker and its first query (per-thread initialization
  /// and lazily built search structures).
  double workerSetupSeconds = 0.0;
  std::int64_t count = 0;      ///< Points queried (a prefix of the set).
  double seconds1 = 0.0;       ///< One worker on one thread.
  double secondsAll = -1.0;    ///< `threads` workers; < 0 when the peer is not thread-safe.
  int threads = 1;
  std::vector<PeerAnswer> answers;    ///< From the 1-thread run, finished.
  std::int64_t threadMismatches = 0;  ///< Answers that differ between the two runs.
};

/// Times `method` on the first points of `set`: a calibration on a few points
/// sets the count to what one thread does in `budgetSeconds` (at least
/// min(maxCount, minCount), at most maxCount), then one timed run with one
/// worker and, when the peer is thread-safe, one with `threads` workers.
PeerRun RunPeer(PeerMethod& method, const PointSet& set, std::int64_t maxCount, std::int64_t minCount,
                double budgetSeconds, int threads);

/// How a peer's distances compare with invmap's on the points both ran.
struct Agreement {
  std::int64_t compared = 0;       ///< Points the peer answered and invmap found.
  std::int64_t peerFarther = 0;    ///< Peer distance > invmap's + tolerance.
  std::int64_t invmapFarther = 0;  ///< invmap distance > peer's + tolerance.
  std::int64_t peerFailed = 0;     ///< Points the peer returned nothing for.
  std::int64_t invmapMissing = 0;  ///< Points invmap did not find (never expected).
  double maxDifference = 0.0;      ///< Largest |peer - invmap| distance over compared points.
};

/// Compares the first answers.size() points; `tolerance` is absolute.
Agreement Compare(const std::vector<PeerAnswer>& answers, const Results& invmapResults, double tolerance);

/// invmap's oracle: the same points solved only on the cell invmap reported,
/// from that cell's center (the cost of the cell solves alone, without the
/// search for the cell).
struct OracleRun {
  double seconds = 0.0;
  std::int64_t count = 0;
  /// Points whose oracle distance differs from invmap's by more than the
  /// tolerance (never expected: the oracle solves on invmap's own cell).
  std::int64_t disagreements = 0;
};

/// Times the oracle on the first `count` points of `set` with one thread.
/// Builds its own copy of the cells (engine::CellStore) from `geometry`,
/// outside the timing.
OracleRun RunOracle(const Geometry& geometry, const PointSet& set, std::int64_t count, const Results& invmapResults,
                    double tolerance);

}  // namespace invmap::bench
