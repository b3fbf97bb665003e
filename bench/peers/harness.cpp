#include "bench/peers/harness.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

namespace invmap::bench {
namespace {

/// Inverts the first `count` points of `set`; aborts the run on a batch error
/// (a harness bug: the workloads are valid).
void Invert(const Manifold& manifold, const PointSet& set, std::int64_t count, int threads, Results* results) {
  InversionOptions options;
  options.threads = threads;
  std::string message;
  const Error error = manifold.Invert(PointsView::Interleaved(set.coords.data(), count, set.dim), options, results,
                                      &message);
  if (error != Error::Ok) {
    std::fprintf(stderr, "invmap_bench_peers: Invert failed: %s\n", message.c_str());
    std::exit(2);
  }
}

/// Sizes every array of `results` for `count` points, so that a timed
/// Invert into it does not allocate and first-touch its output: the peers'
/// answer arrays are also allocated before their clocks start.
void PresizeResults(std::int64_t count, Results* results) {
  const std::size_t n = static_cast<std::size_t>(count);
  results->status.assign(n, Status::Invalid);
  results->patch.assign(n, -1);
  results->cell.assign(n, -1);
  results->params.assign(3 * n, 0.0);
  results->closest.assign(3 * n, 0.0);
  results->distance.assign(n, 0.0);
  results->iterations.assign(n, 0);
}

/// True when two runs of a peer gave the same answer for a point (bit for bit:
/// a peer whose threads share state would show here).
bool SameAnswer(const PeerAnswer& a, const PeerAnswer& b) {
  if (a.failed || b.failed) return a.failed == b.failed;
  return a.distance == b.distance;
}

}  // namespace

double Now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void ParallelChunks(int threads, std::int64_t n, std::int64_t chunk,
                    const std::function<void(int, std::int64_t, std::int64_t)>& fn) {
  std::atomic<std::int64_t> next{0};
  auto body = [&](int thread) {
    for (;;) {
      const std::int64_t begin = next.fetch_add(chunk);
      if (begin >= n) return;
      fn(thread, begin, std::min(n, begin + chunk));
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(body, t);
  body(0);
  for (std::thread& t : pool) t.join();
}

double ParallelCapacity(int threads) {
  // A dependent chain of integer operations: no vectorization, no memory
  // traffic, so only the cores' availability sets its speed.
  auto spin = [](std::uint64_t* out) {
    std::uint64_t x = 88172645463325252ull;
    for (int i = 0; i < 20000000; ++i) {
      x ^= x << 13;
      x ^= x >> 7;
      x ^= x << 17;
      x *= 0x9E3779B97F4A7C15ull;
    }
    *out = x;
  };
  std::vector<std::uint64_t> sink(threads);
  double t0 = Now();
  spin(&sink[0]);
  const double one = Now() - t0;
  t0 = Now();
  ParallelChunks(threads, threads, 1, [&](int, std::int64_t begin, std::int64_t) { spin(&sink[begin]); });
  const double all = Now() - t0;
  volatile std::uint64_t keep = sink[0];  // the loops' results are used
  (void)keep;
  return threads * one / all;
}

InvmapRun RunInvmap(const Manifold& manifold, const PointSet& set, std::int64_t maxCount, double budgetSeconds,
                    int allThreads) {
  InvmapRun run;
  maxCount = std::min(maxCount, set.count());
  // Warm-up: first touches of the per-thread scratch and the thread pool.
  Results scratch;
  const std::int64_t warm = std::min<std::int64_t>(maxCount, 2000);
  Invert(manifold, set, warm, 1, &scratch);
  Invert(manifold, set, warm, allThreads, &scratch);
  // Calibration on a prefix large enough for its buckets to be typical.
  const std::int64_t probe = std::min<std::int64_t>(maxCount, 20000);
  double t0 = Now();
  Invert(manifold, set, probe, 1, &scratch);
  const double rate = probe / std::max(1e-9, Now() - t0);
  const std::int64_t floorCount = std::min<std::int64_t>(maxCount, 100000);
  run.count = std::clamp<std::int64_t>(static_cast<std::int64_t>(rate * budgetSeconds), floorCount, maxCount);

  PresizeResults(run.count, &run.results);
  t0 = Now();
  Invert(manifold, set, run.count, 1, &run.results);
  run.seconds1 = Now() - t0;
  Results all;
  PresizeResults(run.count, &all);
  t0 = Now();
  Invert(manifold, set, run.count, allThreads, &all);
  run.secondsAll = Now() - t0;
  for (std::int64_t i = 0; i < run.count; ++i) {
    const bool same = all.status[i] == run.results.status[i] && all.cell[i] == run.results.cell[i] &&
                      (all.distance[i] == run.results.distance[i] ||
                       (std::isnan(all.distance[i]) && std::isnan(run.results.distance[i])));
    if (!same) ++run.threadMismatches;
    if (run.results.status[i] != Status::Found) ++run.notFound;
  }
  return run;
}

PeerRun RunPeer(PeerMethod& method, const PointSet& set, std::int64_t maxCount, std::int64_t minCount,
                double budgetSeconds, int threads) {
  PeerRun run;
  maxCount = std::min(maxCount, set.count());
  std::vector<std::unique_ptr<PeerWorker>> workers;
  PeerAnswer answer;
  const double setupStart = Now();
  workers.push_back(method.NewWorker());
  workers[0]->Query(set.point(0), &answer);  // warm-up: lazily built state
  run.workerSetupSeconds = Now() - setupStart;
  // Calibration: as many points as fit in a tenth of the budget (at least 5).
  const double calibrationSeconds = std::min(0.3, 0.1 * budgetSeconds);
  double t0 = Now();
  std::int64_t probed = 0;
  while (probed < maxCount && (probed < 5 || Now() - t0 < calibrationSeconds)) {
    workers[0]->Query(set.point(probed), &answer);
    ++probed;
  }
  const double rate = probed / std::max(1e-9, Now() - t0);
  run.count = std::clamp<std::int64_t>(static_cast<std::int64_t>(rate * budgetSeconds), std::min(maxCount, minCount),
                                       maxCount);

  run.answers.assign(run.count, PeerAnswer());
  t0 = Now();
  for (std::int64_t i = 0; i < run.count; ++i) workers[0]->Query(set.point(i), &run.answers[i]);
  run.seconds1 = Now() - t0;
  for (std::int64_t i = 0; i < run.count; ++i) workers[0]->Finish(set.point(i), &run.answers[i]);

  if (method.threadSafe() && threads > 1) {
    run.threads = threads;
    while (static_cast<int>(workers.size()) < threads) {
      workers.push_back(method.NewWorker());
      workers.back()->Query(set.point(0), &answer);
    }
    std::vector<PeerAnswer> answers(run.count);
    t0 = Now();
    ParallelChunks(threads, run.count, 64, [&](int thread, std::int64_t begin, std::int64_t end) {
      for (std::int64_t i = begin; i < end; ++i) workers[thread]->Query(set.point(i), &answers[i]);
    });
    run.secondsAll = Now() - t0;
    for (std::int64_t i = 0; i < run.count; ++i) {
      workers[0]->Finish(set.point(i), &answers[i]);
      if (!SameAnswer(answers[i], run.answers[i])) ++run.threadMismatches;
    }
  }
  return run;
}

Agreement Compare(const std::vector<PeerAnswer>& answers, const Results& invmapResults, double tolerance) {
  Agreement a;
  for (std::size_t i = 0; i < answers.size(); ++i) {
    if (invmapResults.status[i] != Status::Found) {
      ++a.invmapMissing;
      continue;
    }
    if (answers[i].failed || !std::isfinite(answers[i].distance)) {
      ++a.peerFailed;
      continue;
    }
    ++a.compared;
    const double difference = answers[i].distance - invmapResults.distance[i];
    if (difference > tolerance) ++a.peerFarther;
    if (-difference > tolerance) ++a.invmapFarther;
    a.maxDifference = std::max(a.maxDifference, std::abs(difference));
  }
  return a;
}

}  // namespace invmap::bench
