// What a tracker keeps of one pose's cell pairs for the next ones: each
// pair's proved lower bound on its distance (PairSolveResult::lowerBound)
// and how far the models may have moved against each other since.
//
// A rigid motion of B against A moves every point y of B (in B's frame) by
// at most |dR| |y| + |dt|: |dR| the Frobenius norm of the change of the
// rotation (it bounds the spectral norm), |y| at most B's bounding radius
// about its own origin, dt the change of the translation. A pair's distance
// falls by no more than its points move, so a pair proved at L or farther
// is at L - drift or farther after a drift of the models; while that is at
// least the best distance found, the pair needs no solve at all. The drift
// is summed pose after pose (the triangle inequality), so the bound stays
// valid however the models wander, jumps included; a pair whose bound has
// been used up is solved again and records a fresh one.
//
// The same holds for pairs of BVH nodes: the traversal's frontier (where it
// stopped, each pair of nodes with its bound) is kept, and the next pose's
// traversal starts from it, descending only the entries whose bound the
// drift has used up.
//
// And within a pair: the subdomains its last search ended with
// (kernels::PairPartition), for the pairs solved at the last two motions.
// A pair whose distance stays within the drift of the answer (the contact
// pair, and its neighbours across the cells' edges) is searched again at
// every motion; from its partition only the subdomains near its minimum are.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "kernels/pair_problem.h"
#include "kernels/pair_search.h"

namespace invmap::engine {

class PairBoundCache {
 public:
  /// A pair of BVH nodes of A and B where the previous traversal stopped:
  /// pruned by its bound, or a pair of leaves whose cells it solved.
  /// Together these entries cover every pair of cells once.
  struct FrontierEntry {
    int nodeA, nodeB;
    double bound;    ///< No pair of cells under the two nodes is nearer (when recorded).
    double driftAt;  ///< drift() when recorded.
  };

  /// Sets the bound of |y| over B's points in B's frame (once: the models
  /// stay the same).
  void SetRadius(double radiusB) { radius_ = radiusB; }
  bool hasRadius() const { return radius_ >= 0.0; }

  /// The next query's motion of B into A's frame (SetRadius first). The
  /// first call sets the reference.
  void MoveTo(const kernels::RigidMotion& bIntoA);

  /// True when pair (a, b) is proved no nearer than `distance`.
  bool Excludes(std::int64_t a, std::int64_t b, double distance) const;

  /// Pair (a, b) is no nearer than `lowerBound` at the current motion.
  void Record(std::int64_t a, std::int64_t b, double lowerBound);

  /// True when the entry's bound, less the drift since, is still at least `distance`.
  bool Holds(const FrontierEntry& entry, double distance) const {
    return Holds(entry.bound, entry.driftAt, distance);
  }

  /// The previous traversal's frontier, to start the next one from (empty:
  /// start from the roots).
  const std::vector<FrontierEntry>& frontier() const { return frontier_; }
  /// A new frontier (swapped in; `next` gets the old one's storage). A
  /// frontier grown far finer than a traversal from the roots left is
  /// dropped, so the next traversal starts from the roots again.
  void SetFrontier(std::vector<FrontierEntry>* next, bool fromRoots);

  /// The partition pair (a, b)'s last search left (invalid if none): read
  /// by its next search and swapped with what that one leaves. Null for a
  /// pair that cannot be kept.
  kernels::PairPartition* Partition(std::int64_t a, std::int64_t b);
  /// True when pair (a, b) has a valid partition kept.
  bool HasPartition(std::int64_t a, std::int64_t b) const;

  /// Forgets every pair (the models changed).
  void Clear();

  /// The drift summed since the first motion (tests).
  double drift() const { return drift_; }

 private:
  struct Slot {
    std::uint64_t key;
    double bound;    ///< The pair's lower bound when recorded.
    double driftAt;  ///< drift_ when recorded.
  };
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

  bool Holds(double bound, double driftAt, double distance) const;
  std::size_t Find(std::uint64_t key) const;
  void Grow();

  struct KeptPartition {
    kernels::PairPartition partition;
    std::uint64_t usedAt = 0;  ///< The motion (moves_) of its last use.
  };
  std::unordered_map<std::uint64_t, KeptPartition> partitions_;
  std::uint64_t moves_ = 0;

  std::vector<Slot> slots_;
  std::size_t used_ = 0;
  double radius_ = -1.0;
  double drift_ = 0.0;
  bool hasMotion_ = false;
  std::vector<FrontierEntry> frontier_;
  std::size_t rootFrontierSize_ = 0;  ///< The frontier's size after the last traversal from the roots.
  kernels::RigidMotion last_;
};

}  // namespace invmap::engine
