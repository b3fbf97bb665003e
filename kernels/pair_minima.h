// Every local minimum of the distance between TWO cells, certified: the
// pair counterpart of kernels/cell_minima.h over the joint parameters, on
// the factored nets of kernels/pair_nets.h. A pair of subdomains is dropped
// when its bound lies beyond the distance asked for, or when the distance
// is monotone along a parameter whose way down stays inside the cells;
// settled when it is convex enough to hold one minimum (found by a joint
// local solve on the subdomains' own nets); reduced to a face of one cell
// when the distance falls toward that face, or bends down (concave, or a
// saddle) across it everywhere.
#pragma once

#include <vector>

#include "kernels/pair_problem.h"

namespace invmap::kernels {

/// One local minimum of |x(u) - y(v)| over a pair's joint domain.
struct PairMinimum {
  double refA[3] = {0, 0, 0};
  double refB[3] = {0, 0, 0};
  double pointA[3] = {0, 0, 0};  ///< Common frame.
  double pointB[3] = {0, 0, 0};
  double distance = 0.0;
};

struct PairMinimaResult {
  std::vector<PairMinimum> minima;  ///< Unordered; one on an edge of subdomains may repeat.
  bool certified = true;            ///< False when the search ran out of its budget.
};

/// The local minima of the distance between the two cells not farther than
/// `maxDistance` (each is a minimum over the pair's domain; whether it is
/// one of whole models whose cells meet there is the caller's question).
/// Both sides need their DistanceNets.
PairMinimaResult PairLocalMinima(const PairSide& a, const PairSide& b, double maxDistance);

}  // namespace invmap::kernels
