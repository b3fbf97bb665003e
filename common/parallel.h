// Data-parallel loops and sorts for every layer (the engine, the implicit
// grids). This is the only file in invmap that includes TBB: every other file
// states what it wants to run in parallel through the functions below, so the
// threading backend can change here without touching the algorithms. The
// names live in namespace invmap, so the layers' own namespaces
// (invmap::engine, invmap::implicit) find them unqualified.
//
// Results never depend on the thread count: ForEachBlock hands the same
// blocks to `fn` under both policies and for any number of threads, and Sort
// gives one answer whenever the comparison is a strict total order.
#pragma once

#include <algorithm>
#include <cstdint>
#include <thread>

// INVMAP_PAR=0 builds without TBB; ExecutionPolicy::Par then runs the
// sequential code. The default is TBB on: the invmap_common target links it.
#ifndef INVMAP_PAR
#define INVMAP_PAR 1
#endif

#if INVMAP_PAR
#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>
#endif

namespace invmap {

/// Whether a loop or sort may use several threads. Seq and Par produce
/// bit-identical results; Par is only faster.
enum class ExecutionPolicy {
  Seq,  ///< Runs on the calling thread; never touches TBB.
  Par,  ///< Runs as TBB tasks (sequentially when built with INVMAP_PAR=0).
};

/// Number of threads TBB would use by default in this process: the cores
/// this process may run on (affinity mask and cgroup quota respected).
/// Always at least 1.
inline int HardwareThreads() {
#if INVMAP_PAR
  return std::max(1, tbb::info::default_concurrency());
#else
  return std::max(1u, std::thread::hardware_concurrency());
#endif
}

namespace detail {

/// Calls fn(begin, end) on the blocks that tbb::simple_partitioner makes of
/// tbb::blocked_range(begin, end, grain): halve at begin + size / 2 while
/// size > grain. Blocks are visited in increasing order. Recursion depth is
/// log2(size / grain).
template <typename Fn>
void ForEachBlockSeq(std::int64_t begin, std::int64_t end, std::int64_t grain, Fn& fn) {
  if (end - begin > grain) {
    const std::int64_t middle = begin + (end - begin) / 2;
    ForEachBlockSeq(begin, middle, grain, fn);
    ForEachBlockSeq(middle, end, grain, fn);
  } else {
    fn(begin, end);
  }
}

}  // namespace detail

/// Runs body() and waits for it, so that every TBB algorithm it starts,
/// including those inside other libraries built on TBB (Embree's builder),
/// uses at most maxThreads threads. maxThreads <= 0 keeps the caller's task
/// arena (all cores at top level); more than HardwareThreads() runs that
/// many (more threads than cores would only take turns, and TBB prints a
/// warning on stderr when an arena asks for more workers than it allows).
/// Unlike tbb::global_control, the limit applies to this call only, not to
/// the whole process. An exception thrown by body propagates to the caller.
template <typename Body>
void RunWithThreads(int maxThreads, const Body& body) {
#if INVMAP_PAR
  if (maxThreads > 0) {
    tbb::task_arena arena(std::min(maxThreads, HardwareThreads()));
    arena.execute(body);
    return;
  }
#else
  (void)maxThreads;
#endif
  body();
}

/// Calls fn(begin, end) on contiguous blocks that together cover [0, n)
/// exactly once. The blocks are those of a recursive halving until a block
/// holds at most `grain` indices, so they are the same for Seq and Par and
/// for any thread count; a reduction that combines per-block partial results
/// in block order is therefore reproducible.
/// @param n          number of indices; nothing is called when n <= 0.
/// @param grain      largest block size; values below 1 are treated as 1.
/// @param fn         callable as fn(std::int64_t begin, std::int64_t end); with
///                   Par it runs concurrently on disjoint blocks, so it must
///                   only write to data owned by its block. An exception it
///                   throws cancels the remaining blocks and reaches the
///                   caller (TBB rethrows it; Seq simply unwinds).
/// @param maxThreads Par only: upper limit on threads for this call; 0 uses the
///                   caller's task arena (all cores at top level).
template <typename Fn>
void ForEachBlock(ExecutionPolicy policy, std::int64_t n, std::int64_t grain, Fn&& fn,
                  int maxThreads = 0) {
  if (n <= 0) return;
  grain = std::max<std::int64_t>(grain, 1);
#if INVMAP_PAR
  // A single block gains nothing from task overhead.
  if (policy == ExecutionPolicy::Par && n > grain) {
    RunWithThreads(maxThreads, [&] {
      tbb::parallel_for(
          tbb::blocked_range<std::int64_t>(0, n, static_cast<std::size_t>(grain)),
          [&](const tbb::blocked_range<std::int64_t>& range) { fn(range.begin(), range.end()); },
          tbb::simple_partitioner());
    });
    return;
  }
#else
  (void)policy;
  (void)maxThreads;
#endif
  detail::ForEachBlockSeq(0, n, grain, fn);
}

/// Sorts [first, last) by `less`. Not stable: elements that compare equivalent
/// may end in a different order under Seq and Par, so make `less` a strict
/// total order (break ties by an index) whenever the order must be
/// reproducible.
/// @param maxThreads Par only: upper limit on threads; 0 uses the caller's
///                   task arena.
template <typename RandomIt, typename Less>
void Sort(ExecutionPolicy policy, RandomIt first, RandomIt last, Less less, int maxThreads = 0) {
#if INVMAP_PAR
  if (policy == ExecutionPolicy::Par) {
    RunWithThreads(maxThreads, [&] { tbb::parallel_sort(first, last, less); });
    return;
  }
#else
  (void)policy;
  (void)maxThreads;
#endif
  std::sort(first, last, less);
}

}  // namespace invmap
