#include "implicit/refinement_criteria.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "implicit/hull_membership.h"

namespace invmap::implicit {
namespace {

template <int N>
double Dot(const double* a, const double* b) {
  double sum = 0;
  for (int k = 0; k < N; ++k) sum += a[k] * b[k];
  return sum;
}

template <int N>
double MaxDeviation(const CubicProxy<N>& p) {
  double largest = 0;
  for (double d : p.deviation) largest = std::max(largest, std::fabs(d));
  return largest;
}

/// The proxy of a - b (MaterialInterface compares functions by differences).
template <int N>
void Difference(const CubicProxy<N>& a, const CubicProxy<N>& b, CubicProxy<N>* out) {
  for (int k = 0; k < SimplexCounts<N>::kControl; ++k) out->control[k] = a.control[k] - b.control[k];
  for (int k = 0; k < SimplexCounts<N>::kDeviations; ++k) out->deviation[k] = a.deviation[k] - b.deviation[k];
  for (int k = 0; k < N; ++k) out->gradient[k] = a.gradient[k] - b.gradient[k];
  out->lo = out->hi = out->control[0];
  for (double c : out->control) {
    out->lo = std::min(out->lo, c);
    out->hi = std::max(out->hi, c);
  }
}

/// The reference's straddle test of an interval (touching zero counts).
bool Straddles(double lo, double hi) { return lo * hi <= 0; }

}  // namespace

template <int N>
CriteriaEvaluator<N>::CriteriaEvaluator(Mode mode, double epsilon, int functionCount, const std::vector<CsgNode>* tree)
    : mode_(mode),
      epsilon2_(epsilon * epsilon),
      functionCount_(functionCount),
      tree_(tree),
      proxies_(functionCount),
      differences_(3),
      hullPoints_(3 * SimplexCounts<N>::kControl) {
  candidates_.reserve(functionCount);
  if (mode == Mode::Csg) {
    // Post order of the nodes reachable from the root, each once, without
    // recursion (trees may be deep and share nodes).
    std::vector<std::uint8_t> state(tree->size() + 1, 0);  // 0 new, 1 expanded, 2 done
    std::vector<int> stack = {1};
    while (!stack.empty()) {
      const int node = stack.back();
      if (state[node] == 2) {
        stack.pop_back();
        continue;
      }
      if (state[node] == 1) {
        state[node] = 2;
        csgOrder_.push_back(node);
        stack.pop_back();
        continue;
      }
      state[node] = 1;
      const CsgNode& n = (*tree)[node - 1];
      for (int element : {n.a, n.op == CsgNode::Op::Negation ? 0 : n.b})
        if (element > 0 && state[element] == 0) stack.push_back(element);
    }
  }
}

template <int N>
CellVerdict CriteriaEvaluator<N>::Evaluate(const double* const points[N + 1], const VertexSamples samples[N + 1]) {
  frame_.Set(points);
  samples_ = samples;
  switch (mode_) {
    case Mode::Arrangement:
      return Arrangement();
    case Mode::MaterialInterface:
      return MaterialInterface();
    case Mode::Csg:
      return Csg();
  }
  return {};
}

template <int N>
void CriteriaEvaluator<N>::SetProxy(int function, CubicProxy<N>* proxy) const {
  double values[N + 1];
  const double* gradients[N + 1];
  for (int i = 0; i <= N; ++i) {
    values[i] = samples_[i].values[function];
    gradients[i] = samples_[i].gradients + 3 * function;
  }
  proxy->Set(frame_, values, gradients);
}

template <int N>
void CriteriaEvaluator<N>::SetAllProxies() {
  for (int f = 0; f < functionCount_; ++f) SetProxy(f, &proxies_[f]);
}

// Distance test, one function: max |deviation| / |gradient| > epsilon, as
// err^2 D^2 > eps^2 |U|^2 (a flat simplex, D = 0, never refines).
template <int N>
bool CriteriaEvaluator<N>::SingleRefinable(const CubicProxy<N>& p) const {
  const double error = MaxDeviation(p);
  const double d2 = frame_.determinant * frame_.determinant;
  return error * error * d2 > epsilon2_ * Dot<N>(p.gradient, p.gradient);
}

// Distance test, two functions: max_k |M (b_k - bbar_k)| > eps with
// M = g (g^T g)^-1, g = [U_a U_b] / D, computed without division through the
// adjugate of W = G G^T (G has rows U_a, U_b).
template <int N>
bool CriteriaEvaluator<N>::PairRefinable(const CubicProxy<N>& a, const CubicProxy<N>& b) const {
  const double w00 = Dot<N>(a.gradient, a.gradient);
  const double w01 = Dot<N>(a.gradient, b.gradient);
  const double w11 = Dot<N>(b.gradient, b.gradient);
  const double e = w00 * w11 - w01 * w01;
  double h0[N], h1[N];
  for (int k = 0; k < N; ++k) {
    h0[k] = w11 * a.gradient[k] - w01 * b.gradient[k];
    h1[k] = -w01 * a.gradient[k] + w00 * b.gradient[k];
  }
  const double d2 = frame_.determinant * frame_.determinant;
  const double bound = epsilon2_ * e * e;
  for (int k = 0; k < SimplexCounts<N>::kDeviations; ++k) {
    double r2 = 0;
    for (int c = 0; c < N; ++c) {
      const double r = a.deviation[k] * h0[c] + b.deviation[k] * h1[c];
      r2 += r * r;
    }
    if (d2 * r2 > bound) return true;
  }
  return false;
}

// Distance test, three functions (tetrahedra only): M = g^-T, through the
// adjugate of G (rows U_a, U_b, U_c): H's rows are the cross products.
template <int N>
bool CriteriaEvaluator<N>::TripleRefinable(const CubicProxy<N>& a, const CubicProxy<N>& b,
                                           const CubicProxy<N>& c) const {
  if constexpr (N == 3) {
    auto cross = [](const double* x, const double* y, double* out) {
      out[0] = x[1] * y[2] - x[2] * y[1];
      out[1] = x[2] * y[0] - x[0] * y[2];
      out[2] = x[0] * y[1] - x[1] * y[0];
    };
    double h0[3], h1[3], h2[3];
    cross(b.gradient, c.gradient, h0);
    cross(c.gradient, a.gradient, h1);
    cross(a.gradient, b.gradient, h2);
    const double e = Dot<3>(a.gradient, h0);
    const double d2 = frame_.determinant * frame_.determinant;
    const double bound = epsilon2_ * e * e;
    for (int k = 0; k < SimplexCounts<3>::kDeviations; ++k) {
      double r2 = 0;
      for (int m = 0; m < 3; ++m) {
        const double r = a.deviation[k] * h0[m] + b.deviation[k] * h1[m] + c.deviation[k] * h2[m];
        r2 += r * r;
      }
      if (d2 * r2 > bound) return true;
    }
    return false;
  } else {
    (void)a, (void)b, (void)c;
    return false;
  }
}

template <int N>
bool CriteriaEvaluator<N>::HullContainsOrigin(const CubicProxy<N>* const* proxies, int m) {
  constexpr int kControl = SimplexCounts<N>::kControl;
  for (int k = 0; k < kControl; ++k)
    for (int c = 0; c < m; ++c) hullPoints_[m * k + c] = proxies[c]->control[k];
  return m == 2 ? OriginInConvexHull2d(hullPoints_.data(), kControl) : OriginInConvexHull3d(hullPoints_.data(), kControl);
}

// Pairs of candidates whose hull holds the origin, then (with at least 3 such
// pairs, in 3D) triples whose three pairs all passed.
template <int N>
bool CriteriaEvaluator<N>::PairsOrTriplesRefinable() {
  const int count = static_cast<int>(candidates_.size());
  if (count < 2) return false;
  pairPasses_.assign(static_cast<std::size_t>(count) * count, 0);
  int pairsPassing = 0;
  for (int i = 0; i < count; ++i) {
    for (int j = i + 1; j < count; ++j) {
      const CubicProxy<N>* pair[2] = {&proxies_[candidates_[i]], &proxies_[candidates_[j]]};
      if (!HullContainsOrigin(pair, 2)) continue;
      ++pairsPassing;
      pairPasses_[i * count + j] = 1;
      if (PairRefinable(*pair[0], *pair[1])) return true;
    }
  }
  if (N < 3 || pairsPassing < 3) return false;
  for (int i = 0; i < count; ++i) {
    for (int j = i + 1; j < count; ++j) {
      if (!pairPasses_[i * count + j]) continue;
      for (int l = j + 1; l < count; ++l) {
        if (!pairPasses_[i * count + l] || !pairPasses_[j * count + l]) continue;
        const CubicProxy<N>* triple[3] = {&proxies_[candidates_[i]], &proxies_[candidates_[j]],
                                          &proxies_[candidates_[l]]};
        if (HullContainsOrigin(triple, 3) && TripleRefinable(*triple[0], *triple[1], *triple[2])) return true;
      }
    }
  }
  return false;
}

template <int N>
CellVerdict CriteriaEvaluator<N>::Arrangement() {
  CellVerdict verdict;
  candidates_.clear();
  const double* values[N + 1];
  const double* norms[N + 1];
  for (int i = 0; i <= N; ++i) {
    values[i] = samples_[i].values;
    norms[i] = samples_[i].gradientNorms;
  }
  for (int f = 0; f < functionCount_; ++f) {
    if (CertainlyNoCrossing<N>(values, norms, f, frame_.longestEdge)) continue;
    CubicProxy<N>& proxy = proxies_[f];
    SetProxy(f, &proxy);
    if (!proxy.Crosses()) continue;
    verdict.active = true;
    candidates_.push_back(f);
    if (SingleRefinable(proxy)) {
      verdict.refinable = true;
      return verdict;
    }
  }
  verdict.refinable = PairsOrTriplesRefinable();
  return verdict;
}

// Material i is where f_i is largest. Candidates: functions whose upper bound
// exceeds every function's lower bound; their differences are tested like an
// arrangement's functions (pairs: f_j - f_i = 0; triples and quadruples: the
// hull of consecutive differences).
template <int N>
CellVerdict CriteriaEvaluator<N>::MaterialInterface() {
  CellVerdict verdict;
  // Most functions are far below the largest one. Bound each function's
  // control values from vertex data (as in CertainlyNoCrossing: within
  // max |g| L / 2 of the vertex values), and build proxies only for
  // functions that can be candidates or can hold the largest lower bound.
  bounds_.resize(functionCount_);
  double largestLowBound = -std::numeric_limits<double>::infinity();
  for (int f = 0; f < functionCount_; ++f) {
    double lowest = samples_[0].values[f], highest = lowest, steepest = 0;
    for (int i = 0; i <= N; ++i) {
      lowest = std::min(lowest, samples_[i].values[f]);
      highest = std::max(highest, samples_[i].values[f]);
      steepest = std::max(steepest, samples_[i].gradientNorms[f]);
    }
    const double spread = 0.5 * (1 + 1e-9) * steepest * frame_.longestEdge + 1e-12 * (std::fabs(lowest) + std::fabs(highest));
    bounds_[f] = {lowest - spread, highest + spread, lowest, false};
    largestLowBound = std::max(largestLowBound, bounds_[f].loLower);
  }
  double largestLow = -std::numeric_limits<double>::infinity();
  for (int f = 0; f < functionCount_; ++f) {
    // hi_f <= hiUpper and lo_f <= loUpper: a function failing both tests is
    // neither a candidate nor the holder of the largest lower bound.
    if (bounds_[f].hiUpper <= largestLowBound && bounds_[f].loUpper < largestLowBound) {
      bounds_[f].computed = false;
      continue;
    }
    bounds_[f].computed = true;
    SetProxy(f, &proxies_[f]);
    largestLow = std::max(largestLow, proxies_[f].lo);
  }
  candidates_.clear();
  for (int f = 0; f < functionCount_; ++f)
    if (bounds_[f].computed && proxies_[f].hi > largestLow) candidates_.push_back(f);
  const int count = static_cast<int>(candidates_.size());
  if (count < 2) return verdict;

  pairPasses_.assign(static_cast<std::size_t>(count) * count, 0);
  CubicProxy<N>& d0 = differences_[0];
  CubicProxy<N>& d1 = differences_[1];
  CubicProxy<N>& d2 = differences_[2];
  for (int i = 0; i < count; ++i) {
    for (int j = i + 1; j < count; ++j) {
      Difference(proxies_[candidates_[j]], proxies_[candidates_[i]], &d0);
      if (!d0.Crosses()) continue;
      verdict.active = true;
      pairPasses_[i * count + j] = 1;
      if (SingleRefinable(d0)) {
        verdict.refinable = true;
        return verdict;
      }
    }
  }
  auto passes = [&](int i, int j) { return pairPasses_[i * count + j] != 0; };
  int triplesPassing = 0;
  for (int i = 0; i < count; ++i) {
    for (int j = i + 1; j < count; ++j) {
      if (!passes(i, j)) continue;
      for (int l = j + 1; l < count; ++l) {
        if (!passes(i, l) || !passes(j, l)) continue;
        Difference(proxies_[candidates_[i]], proxies_[candidates_[j]], &d0);
        Difference(proxies_[candidates_[j]], proxies_[candidates_[l]], &d1);
        const CubicProxy<N>* pair[2] = {&d0, &d1};
        if (!HullContainsOrigin(pair, 2)) continue;
        ++triplesPassing;
        if (PairRefinable(d0, d1)) {
          verdict.refinable = true;
          return verdict;
        }
      }
    }
  }
  if (N < 3 || triplesPassing < 4) return verdict;
  for (int i = 0; i < count; ++i) {
    for (int j = i + 1; j < count; ++j) {
      if (!passes(i, j)) continue;
      for (int l = j + 1; l < count; ++l) {
        if (!passes(i, l) || !passes(j, l)) continue;
        for (int m = l + 1; m < count; ++m) {
          if (!passes(i, m) || !passes(j, m) || !passes(l, m)) continue;
          Difference(proxies_[candidates_[i]], proxies_[candidates_[j]], &d0);
          Difference(proxies_[candidates_[j]], proxies_[candidates_[l]], &d1);
          Difference(proxies_[candidates_[l]], proxies_[candidates_[m]], &d2);
          const CubicProxy<N>* triple[3] = {&d0, &d1, &d2};
          if (HullContainsOrigin(triple, 3) && TripleRefinable(d0, d1, d2)) {
            verdict.refinable = true;
            return verdict;
          }
        }
      }
    }
  }
  return verdict;
}

// The tree's interval over the cell, node by node in post order (a node
// shared by several parents is evaluated once), from the functions' proxy
// intervals. A node's candidates are those of its operands whose interval
// straddles zero, kept only if its own interval straddles too.
template <int N>
CellVerdict CriteriaEvaluator<N>::Csg() {
  CellVerdict verdict;
  SetAllProxies();
  const std::size_t k = static_cast<std::size_t>(functionCount_);
  nodeIntervals_.resize(tree_->size() + 1);
  nodeCandidates_.assign((tree_->size() + 1) * k, 0);
  for (int node : csgOrder_) {
    const CsgNode& n = (*tree_)[node - 1];
    std::uint8_t* mine = &nodeCandidates_[node * k];
    const int operands = n.op == CsgNode::Op::Negation ? 1 : 2;
    Interval child[2];
    for (int c = 0; c < operands; ++c) {
      const int element = c == 0 ? n.a : n.b;
      child[c] = element < 0 ? Interval{proxies_[-element - 1].lo, proxies_[-element - 1].hi} : nodeIntervals_[element];
      if (!Straddles(child[c].lo, child[c].hi)) continue;
      if (element < 0) {
        mine[-element - 1] = 1;
      } else {
        const std::uint8_t* theirs = &nodeCandidates_[element * k];
        for (std::size_t f = 0; f < k; ++f) mine[f] |= theirs[f];
      }
    }
    Interval& result = nodeIntervals_[node];
    switch (n.op) {
      case CsgNode::Op::Intersection:
        result = {std::max(child[0].lo, child[1].lo), std::max(child[0].hi, child[1].hi)};
        break;
      case CsgNode::Op::Union:
        result = {std::min(child[0].lo, child[1].lo), std::min(child[0].hi, child[1].hi)};
        break;
      case CsgNode::Op::Negation:
        result = {-child[0].hi, -child[0].lo};
        break;
    }
    if (!Straddles(result.lo, result.hi)) std::fill(mine, mine + k, 0);
  }
  const Interval& root = nodeIntervals_[1];
  if (!Straddles(root.lo, root.hi)) return verdict;
  candidates_.clear();
  for (std::size_t f = 0; f < k; ++f)
    if (nodeCandidates_[k + f]) candidates_.push_back(static_cast<int>(f));
  verdict.active = !candidates_.empty();
  for (int f : candidates_) {
    if (SingleRefinable(proxies_[f])) {
      verdict.refinable = true;
      return verdict;
    }
  }
  verdict.refinable = PairsOrTriplesRefinable();
  return verdict;
}

template class CriteriaEvaluator<2>;
template class CriteriaEvaluator<3>;

}  // namespace invmap::implicit
