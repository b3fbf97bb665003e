// The closest points between two cells, certified: a local solve over the
// joint parameters (kernels/pair_local_solve.h) made global over the pair
// by a branch and bound over pairs of subdomains, bounded below by the
// factored Bernstein nets of the squared distance (kernels/pair_nets.h)
// and closed around KKT points by kernels/pair_certificate.h. Affine
// segment and triangle pairs are solved in closed form.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "kernels/pair_problem.h"

namespace invmap::kernels {

/// Outcome of one pair's solve.
enum class PairStatus : std::uint8_t {
  Converged,            ///< Global minimum over the pair, both points inside their domains.
  ProjectedToBoundary,  ///< Global minimum over the pair, some point on its domain's boundary.
  NotCertified,         ///< Best pair found; the search budget ran out first.
  Farther,              ///< No pair of points is closer than the caller's bound.
};

struct PairSolveResult {
  double refA[3] = {0, 0, 0};     ///< Reference coordinates on A (paramDim used).
  double refB[3] = {0, 0, 0};     ///< On B.
  double pointA[3] = {0, 0, 0};   ///< A's closest point, common frame.
  double pointB[3] = {0, 0, 0};   ///< B's.
  double distance = 0.0;
  PairStatus status = PairStatus::Farther;
  int iterations = 0;             ///< Newton iterations of every local solve.
  int subdomains = 0;             ///< Pairs of subdomains the search examined.
  /// NotCertified: a lower bound of the squared distance over the parts of
  /// the pair the search left open (a caller that finds a closer pair
  /// elsewhere needs no more of this one); +inf otherwise.
  double openBound2 = std::numeric_limits<double>::infinity();
  /// No pair of points of the two cells is nearer than this (to the
  /// search's tolerance): the pair's distance when certified, else what the
  /// nets, the bound it was searched under and its open parts prove. 0
  /// when nothing is proved. A tracker keeps it for the next poses.
  double lowerBound = 0.0;
};

/// The subdomains a certified pair search ended with (trackers): the next
/// motion of the same two cells starts its search from them instead of from
/// the whole pair. Each keeps its subdomain, its nets in the cells' own
/// frames (PairNets::BuildRootOwn, split as its placed nets were) and the
/// lower bound of the distance its nets proved, with the drift (the models'
/// summed motion, engine/pair_bound_cache.h) when proved. A later motion
/// skips a subdomain whose bound, less the drift since, still reaches the
/// level the search prunes at; the rest are placed at the new motion and
/// searched as the search's own subdomains are. Together they cover the
/// pair once, so the search stays a search of the whole pair.
struct PairPartition {
  bool valid = false;  ///< Left by a certified search of an untrimmed pair.
  int leafLength = 0;  ///< Doubles per subdomain.
  std::vector<double> leaves;
  /// Subdomains the last search from the whole pair ended with: a partition
  /// grown far finer (reopened subdomains are split again, never merged)
  /// is dropped, and the next search starts from the whole pair.
  std::size_t wholeLeaves = 0;
  /// The best point found (joint reference coordinates), where the next
  /// search's first local solve starts.
  double start[kMaxPairParams] = {};
};

/// A tracker's partitions for one pair solve.
struct PairReuse {
  const PairPartition* previous = nullptr;  ///< Read (null or invalid: from the whole pair).
  PairPartition* next = nullptr;            ///< Written: this search's (a different object).
  double drift = 0.0;                       ///< The models' summed motion now.
};

/// Scratch memory of the pair search; one per thread.
struct PairWorkspace {
  std::vector<double> slots;
  std::vector<int> freeSlots;
  std::vector<int> heap;
  std::vector<double> scratch;
  std::vector<double> hessianScratch;
};

/// True when the side is an affine segment or triangle (closed form).
bool IsAffineSimplexSide(const PairSide& side);

/// The global minimum of |x(u) - y(v)| over the pair, within the distance
/// tolerance (kernels/tolerances.h) of the larger cell's size. `startA`,
/// `startB` (optional, both or neither) seed the first local solve.
/// `bound2`: the squared distance of the best pair found elsewhere; a pair
/// that cannot beat it returns Farther (often without any Newton step).
/// Curved cells need their DistanceNets (PairSide::nets).
/// `reuse` (optional): a tracker's partitions of this pair (PairPartition).
PairSolveResult SolveCellPair(const PairSide& a, const PairSide& b, const double* startA, const double* startB,
                              PairWorkspace* ws, double bound2 = std::numeric_limits<double>::infinity(),
                              const PairReuse* reuse = nullptr);

/// A quick look at a pair, for a caller that searches pairs only once it
/// knows how near the models come: Farther when the pair's nets keep it at
/// bound2 or beyond; else one local solve from where the nets come closest,
/// its point returned with status NotCertified and openBound2 the nets'
/// lower bound over the whole pair (SolveCellPair certifies it later). Two
/// affine cells are solved at once, as SolveCellPair does.
PairSolveResult ProbeCellPair(const PairSide& a, const PairSide& b, PairWorkspace* ws,
                              double bound2 = std::numeric_limits<double>::infinity());

/// The least squared distance the factored nets allow between the two
/// cells (less their rounding): a lower bound without any solve.
double PairNetLowerBound(const PairSide& a, const PairSide& b, PairWorkspace* ws);

}  // namespace invmap::kernels
