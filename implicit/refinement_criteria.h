// The refinement criteria of one simplex (sections 3.2 and 3.3 of
// docs/grids.md) for the three modes:
// is the simplex refinable, and is it active (does it pass the mode's
// zero-crossing test)? The order of the tests and their comparisons follow
// the reference implementation so grids match its cell counts.
#pragma once

#include <cstdint>
#include <vector>

#include "implicit/cubic_proxy.h"
#include "invmap/implicit.h"

namespace invmap::implicit {

struct CellVerdict {
  bool refinable = false;
  bool active = false;
};

/// Per vertex: the k function values, their gradients (3 per function) and
/// the gradients' norms (over the first N coordinates).
struct VertexSamples {
  const double* values;
  const double* gradients;
  const double* gradientNorms;
};

/// Decides CellVerdicts. Holds scratch space: one per thread.
template <int N>
class CriteriaEvaluator {
 public:
  /// `tree` (Mode::Csg) must be valid for `functionCount` and outlive this.
  CriteriaEvaluator(Mode mode, double epsilon, int functionCount, const std::vector<CsgNode>* tree);

  /// `points[i]` (3 coordinates) and `samples[i]` describe vertex i.
  CellVerdict Evaluate(const double* const points[N + 1], const VertexSamples samples[N + 1]);

 private:
  struct Interval {
    double lo, hi;
  };

  CellVerdict Arrangement();
  CellVerdict MaterialInterface();
  CellVerdict Csg();
  /// Proxies of every function (Csg needs every interval).
  void SetAllProxies();
  /// Pair and triple stages shared by Arrangement and Csg on `candidates_`.
  bool PairsOrTriplesRefinable();
  void SetProxy(int function, CubicProxy<N>* proxy) const;

  bool SingleRefinable(const CubicProxy<N>& p) const;
  bool PairRefinable(const CubicProxy<N>& a, const CubicProxy<N>& b) const;
  bool TripleRefinable(const CubicProxy<N>& a, const CubicProxy<N>& b, const CubicProxy<N>& c) const;
  bool HullContainsOrigin(const CubicProxy<N>* const* proxies, int m);

  Mode mode_;
  double epsilon2_;
  int functionCount_;
  const std::vector<CsgNode>* tree_;

  // The current simplex.
  SimplexFrame<N> frame_;
  const VertexSamples* samples_ = nullptr;

  /// MaterialInterface: bounds of a function's control values from vertex data.
  struct ValueBounds {
    double loLower, hiUpper, loUpper;
    bool computed;  ///< Its proxy was built.
  };

  std::vector<CubicProxy<N>> proxies_;   ///< One per function.
  std::vector<ValueBounds> bounds_;
  std::vector<int> candidates_;          ///< Functions taking part in pairs and triples.
  std::vector<std::uint8_t> pairPasses_; ///< candidates^2: the pair's hull contains the origin.
  std::vector<CubicProxy<N>> differences_;
  std::vector<int> csgOrder_;               ///< Csg: the tree's nodes in post order.
  std::vector<Interval> nodeIntervals_;     ///< Csg: per node (1-based).
  std::vector<std::uint8_t> nodeCandidates_;  ///< Csg: per node, per function.
  std::vector<double> hullPoints_;
};

extern template class CriteriaEvaluator<2>;
extern template class CriteriaEvaluator<3>;

}  // namespace invmap::implicit
