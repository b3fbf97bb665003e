#include "kernels/bernstein_net.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "kernels/interval_matrix.h"
#include "kernels/simplex_index.h"

namespace invmap::kernels {
namespace {

/// Per-factor basis sizes and strides of a tensor net (first factor fastest).
struct NetLayout {
  int numFactors = 0;
  int count[kMaxFactors] = {1, 1, 1};
  int stride[kMaxFactors] = {1, 1, 1};
  const SimplexIndex* index[kMaxFactors] = {nullptr, nullptr, nullptr};

  explicit NetLayout(const CellShape& shape) : numFactors(shape.numFactors()) {
    int s = 1;
    for (int f = 0; f < numFactors; ++f) {
      const SimplexFactor& fac = shape.factor(f);
      index[f] = &SimplexIndex::Get(fac.dim, fac.degree);
      count[f] = index[f]->size();
      stride[f] = s;
      s *= count[f];
    }
  }
  int Position(int flat, int f) const { return (flat / stride[f]) % count[f]; }
};


/// The rule of one simplex-factor split: child coefficient at position k is
/// the sum over [start[k], start[k+1]) of weight * parent coefficient at source.
struct SplitRule {
  std::vector<int> start;
  std::vector<int> source;
  std::vector<double> weight;
};

/// Blossom of the net at the child's vertices, where vertex j is the
/// midpoint (e_i + e_j) / 2: expanding the alpha_j midpoint arguments gives
/// b'_alpha = sum_m C(alpha_j, m) 2^-alpha_j b_{alpha with (alpha_i + alpha_j - m) at i, m at j}.
SplitRule BuildSplitRule(int dim, int degree, int i, int j) {
  const SimplexIndex& index = SimplexIndex::Get(dim, degree);
  SplitRule rule;
  rule.start.push_back(0);
  for (int k = 0; k < index.size(); ++k) {
    const std::array<int, 4>& alpha = index.multi(k);
    const int aj = alpha[j];
    std::array<int, 4> src = alpha;
    for (int m = 0; m <= aj; ++m) {
      src[j] = m;
      src[i] = alpha[i] + aj - m;
      rule.source.push_back(index.Position(src));
      rule.weight.push_back(Binomial(aj, m) * std::ldexp(1.0, -aj));
    }
    rule.start.push_back(static_cast<int>(rule.source.size()));
  }
  return rule;
}

/// The shared rule for (dim, degree, i, j), built on first use.
const SplitRule& GetSplitRule(int dim, int degree, int i, int j) {
  constexpr int kDegrees = kMaxNetDegree + 1;
  static std::once_flag once[3][kDegrees][4][4];
  static SplitRule rules[3][kDegrees][4][4];
  std::call_once(once[dim - 1][degree][i][j], [&] { rules[dim - 1][degree][i][j] = BuildSplitRule(dim, degree, i, j); });
  return rules[dim - 1][degree][i][j];
}

/// SplitNet one coefficient at a time: `blocks` x `stride` lines of `count`
/// coefficients `stride` apart (kContiguous: stride 1, known to the compiler).
template <bool kContiguous>
void ApplyRuleEach(const SplitRule& rule, int count, int stride, int blocks, const double* in, double* out) {
  const int step = kContiguous ? 1 : stride;
  const int* start = rule.start.data();
  const int* source = rule.source.data();
  const double* weight = rule.weight.data();
  for (int block = 0; block < blocks; ++block) {
    for (int inner = 0; inner < step; ++inner) {
      const double* from = in + block * step * count + inner;
      double* to = out + block * step * count + inner;
      for (int k = 0; k < count; ++k) {
        double sum = 0.0;
        for (int e = start[k]; e < start[k + 1]; ++e) sum += weight[e] * from[source[e] * step];
        to[k * step] = sum;
      }
    }
  }
}

/// Appends one row of a Hessian entry (its (source, weight) terms, sources
/// ascending) to `runs`, extending the last run when the row applies the
/// same rule one place further on.
void AppendRow(const std::vector<std::pair<int, double>>& row, std::vector<HessianRun>* runs) {
  HessianRun next;
  next.first = row.empty() ? 0 : row.front().first;
  next.length = 1;
  next.terms = static_cast<int>(row.size());
  for (int t = 0; t < next.terms; ++t) {
    next.offset[t] = row[t].first - next.first;
    next.weight[t] = row[t].second;
  }
  if (!runs->empty()) {
    HessianRun& last = runs->back();
    bool same = last.terms == next.terms && last.first + last.length == next.first;
    for (int t = 0; same && t < next.terms; ++t) {
      same = last.offset[t] == next.offset[t] && last.weight[t] == next.weight[t];
    }
    if (same) {
      ++last.length;
      return;
    }
  }
  runs->push_back(next);
}

/// Folds the rows of `run` into the range [*lo, *hi]. Each row is summed from
/// 0.0 in term order, exactly as the sparse rule reads, so no row is -0 and
/// the range does not depend on the order the rows are folded in.
/// *nonFinite turns NaN when a row is infinite or NaN (a difference of
/// coefficients near the overflow threshold): min and max would skip a NaN
/// row, and an infinite one bounds nothing.
/// With `noise` (kNoisy), coefficient i of f carries rounding up to
/// noise.scale * noise.weights[i], and each row's range is widened by its share.
template <int kTerms, bool kNoisy>
void RunRange(const HessianRun& run, const double* f, const NetNoise& noise, double* lo, double* hi,
              double* nonFinite) {
  const int terms = kTerms > 0 ? kTerms : run.terms;
  const double* at = f + run.first;
  const double* weights = kNoisy ? noise.weights + run.first : nullptr;
  double l = *lo, h = *hi, check = *nonFinite;
  for (int k = 0; k < run.length; ++k) {
    double v = 0.0;
    for (int t = 0; t < terms; ++t) v += run.weight[t] * at[k + run.offset[t]];
    if constexpr (kNoisy) {
      double spread = 0.0;
      for (int t = 0; t < terms; ++t) spread += std::abs(run.weight[t]) * weights[k + run.offset[t]];
      l = std::min(l, v - noise.scale * spread);
      h = std::max(h, v + noise.scale * spread);
    } else {
      l = std::min(l, v);
      h = std::max(h, v);
    }
    check += v * 0.0;  // 0 for a finite row, NaN otherwise
  }
  *lo = l;
  *hi = h;
  *nonFinite = check;
}

}  // namespace

void SplitNet(const CellShape& shape, int factor, int i, int j, const double* in, double* out) {
  const SimplexFactor& fac = shape.factor(factor);
  const SplitRule& rule = GetSplitRule(fac.dim, fac.degree, i, j);
  int stride = 1;
  for (int f = 0; f < factor; ++f) stride *= SimplexBasisSize(shape.factor(f).dim, shape.factor(f).degree);
  const int count = SimplexBasisSize(fac.dim, fac.degree);
  const int blocks = NetSize(shape) / (stride * count);
  // The rule acts along the factor's axis, for every index of the other
  // factors; each coefficient is summed in the rule's order, so the three
  // loop orders below give the same bits.
  constexpr int kSliceStride = 8;
  if (stride == 1) {
    ApplyRuleEach<true>(rule, count, stride, blocks, in, out);
    return;
  }
  if (stride < kSliceStride) {
    ApplyRuleEach<false>(rule, count, stride, blocks, in, out);
    return;
  }
  // Long enough slices of coefficients sharing the other factors' lower
  // indices are contiguous: the rule is applied to whole slices, which vectorizes.
  for (int block = 0; block < blocks; ++block) {
    const double* from = in + block * stride * count;
    double* to = out + block * stride * count;
    for (int k = 0; k < count; ++k) {
      double* __restrict slice = to + k * stride;
      std::fill(slice, slice + stride, 0.0);
      for (int e = rule.start[k]; e < rule.start[k + 1]; ++e) {
        const double w = rule.weight[e];
        const double* __restrict src = from + rule.source[e] * stride;
        for (int inner = 0; inner < stride; ++inner) slice[inner] += w * src[inner];
      }
    }
  }
}

namespace {

/// Calls visit(a, b, factor, i, j) once for every pair of neighbouring
/// coefficients a, b of a net on `shape`: their multi-indices in factor
/// `factor` differ by one unit moved from barycentric index i to j > i.
template <typename Visit>
void ForEachNeighbourPair(const CellShape& shape, Visit visit) {
  const NetLayout layout(shape);
  const int n = NetSize(shape);
  for (int f = 0; f < layout.numFactors; ++f) {
    const int dim = shape.factor(f).dim;
    const int stride = layout.stride[f], count = layout.count[f];
    if (dim == 1) {
      // A line factor's only edge: neighbours are one stride apart.
      for (int outer = 0; outer < n; outer += stride * count) {
        for (int k = 0; k + 1 < count; ++k) {
          const int first = outer + k * stride;
          for (int a = first; a < first + stride; ++a) visit(a, a + stride, f, 0, 1);
        }
      }
      continue;
    }
    const SimplexIndex& index = *layout.index[f];
    for (int c = 0; c < n; ++c) {
      const int position = layout.Position(c, f);
      const std::array<int, 4>& multi = index.multi(position);
      for (int i = 0; i <= dim; ++i) {
        if (multi[i] == 0) continue;
        for (int j = i + 1; j <= dim; ++j) {
          std::array<int, 4> next = multi;
          --next[i];
          ++next[j];
          visit(c, c + (index.Position(next) - position) * stride, f, i, j);
        }
      }
    }
  }
}

}  // namespace

double SteepestRatioEdge(const CellShape& shape, const double* w, int* factor, int* vi, int* vj) {
  // steepest = high / low, updated only when a pair beats it (products
  // compare without dividing: this runs at every split of a rational cell).
  double high = 1.0, low = 1.0;
  *factor = 0;
  *vi = 0;
  *vj = 1;
  ForEachNeighbourPair(shape, [&](int a, int b, int f, int i, int j) {
    const double big = std::max(w[a], w[b]), small = std::min(w[a], w[b]);
    if (big * low > high * small) {
      high = big;
      low = small;
      *factor = f;
      *vi = i;
      *vj = j;
    }
  });
  return high / low;
}

double SteepestDifferenceEdge(const CellShape& shape, const double* values, int* factor, int* vi, int* vj) {
  double steepest = 0.0;
  *factor = 0;
  *vi = 0;
  *vj = 1;
  ForEachNeighbourPair(shape, [&](int a, int b, int f, int i, int j) {
    const double difference = std::abs(values[a] - values[b]);
    if (difference > steepest) {
      steepest = difference;
      *factor = f;
      *vi = i;
      *vj = j;
    }
  });
  return steepest;
}

double MostBentLine(const CellShape& shape, const double* q, const double* ww, double level, int* factor) {
  const NetLayout layout(shape);
  const int n = NetSize(shape);
  double most = 0.0;
  *factor = 0;
  for (int f = 0; f < layout.numFactors; ++f) {
    // A line's triples start at every coefficient of a block of the net but
    // its last two lines: one contiguous run per block.
    const int stride = layout.stride[f], count = layout.count[f];
    double factorMost = 0.0;
    for (int outer = 0; outer < n; outer += stride * count) {
      for (int a = outer; a < outer + stride * (count - 2); ++a) {
        const int b = a + stride, c = a + 2 * stride;
        const double dq = q[a] - 2.0 * q[b] + q[c];
        factorMost = std::max(factorMost, std::abs(ww ? dq - level * (ww[a] - 2.0 * ww[b] + ww[c]) : dq));
      }
    }
    if (factorMost > most) {
      most = factorMost;
      *factor = f;
    }
  }
  return most;
}

namespace {

/// One factor of a product of nets: for each pair of positions (pa, pb) of
/// the two factors, the position of the sum of their multi-indices in the
/// product's factor and the weight C(alpha) C(beta) / C(alpha + beta) of
/// B^p_alpha B^q_beta = weight B^{p+q}_{alpha+beta} (C the multinomial
/// coefficients; at most 1, so a weighted term never exceeds the product of
/// its coefficients). A missing factor is one position of weight 1.
struct FactorProduct {
  int countA = 1, countB = 1;
  std::vector<int> target{0};      ///< [pa * countB + pb]: position in the product factor.
  std::vector<double> weight{1.0};  ///< [pa * countB + pb].

  /// The table of a factor of dimension `dim` and degrees a and b, built
  /// once per process (a degree-8 tet's is 330 KB; allocated per product it
  /// cost more than the product). Thread-safe.
  static const FactorProduct& Get(int dim, int degreeA, int degreeB) {
    static std::mutex mutex;
    static std::map<std::array<int, 3>, std::unique_ptr<const FactorProduct>> cache;
    std::lock_guard<std::mutex> lock(mutex);
    std::unique_ptr<const FactorProduct>& entry = cache[{dim, degreeA, degreeB}];
    if (!entry) {
      entry = std::make_unique<const FactorProduct>(SimplexIndex::Get(dim, degreeA), SimplexIndex::Get(dim, degreeB),
                                                    SimplexIndex::Get(dim, degreeA + degreeB));
    }
    return *entry;
  }

  FactorProduct() = default;
  FactorProduct(const SimplexIndex& a, const SimplexIndex& b, const SimplexIndex& product)
      : countA(a.size()), countB(b.size()), target(static_cast<size_t>(countA) * countB),
        weight(static_cast<size_t>(countA) * countB) {
    for (int pa = 0; pa < countA; ++pa) {
      for (int pb = 0; pb < countB; ++pb) {
        const std::array<int, 4>& ma = a.multi(pa);
        const std::array<int, 4>& mb = b.multi(pb);
        const int ps = product.Position(std::array<int, 4>{ma[0] + mb[0], ma[1] + mb[1], ma[2] + mb[2], ma[3] + mb[3]});
        target[static_cast<size_t>(pa) * countB + pb] = ps;
        weight[static_cast<size_t>(pa) * countB + pb] = a.multinomial(pa) * b.multinomial(pb) / product.multinomial(ps);
      }
    }
  }
};

}  // namespace

void MultiplyNets(const CellShape& a, const double* netA, const CellShape& b, const double* netB, double* out) {
  std::array<int, kMaxFactors> degrees{};
  for (int f = 0; f < a.numFactors(); ++f) degrees[f] = a.factor(f).degree + b.factor(f).degree;
  const CellShape product(a.type(), degrees);
  const NetLayout la(a), lb(b), lp(product);
  std::fill(out, out + NetSize(product), 0.0);
  // Per factor, the pairs' targets and weights (a missing factor: one
  // position). The loops below run over the pairs of coefficients in flat
  // order (first factor fastest), a before b, and the innermost one over
  // factor 0 of b reads b, the weights and (for a line) the product
  // contiguously: a product of two degree-8 hexes' nets is 531,441 pairs,
  // and locating each pair through multi-indices cost a hundred times more
  // than its arithmetic (a degree-8 volume of 1,728 cells took 107 s to
  // build; see docs/limitations.md).
  static const FactorProduct kMissing;
  const FactorProduct* factors[kMaxFactors] = {&kMissing, &kMissing, &kMissing};
  for (int f = 0; f < la.numFactors; ++f) {
    factors[f] = &FactorProduct::Get(a.factor(f).dim, a.factor(f).degree, b.factor(f).degree);
  }
  const FactorProduct &f0 = *factors[0], &f1 = *factors[1], &f2 = *factors[2];
  const bool line0 = a.factor(0).dim == 1;
  for (int pa2 = 0; pa2 < f2.countA; ++pa2) {
    for (int pa1 = 0; pa1 < f1.countA; ++pa1) {
      for (int pa0 = 0; pa0 < f0.countA; ++pa0) {
        const double coefA = netA[pa0 + pa1 * la.stride[1] + pa2 * la.stride[2]];
        if (coefA == 0.0) continue;
        const int* target0 = &f0.target[static_cast<size_t>(pa0) * f0.countB];
        const double* weight0 = &f0.weight[static_cast<size_t>(pa0) * f0.countB];
        for (int pb2 = 0; pb2 < f2.countB; ++pb2) {
          const std::size_t pair2 = static_cast<size_t>(pa2) * f2.countB + pb2;
          for (int pb1 = 0; pb1 < f1.countB; ++pb1) {
            const std::size_t pair1 = static_cast<size_t>(pa1) * f1.countB + pb1;
            const double scaled = coefA * f1.weight[pair1] * f2.weight[pair2];
            const int base = f1.target[pair1] * lp.stride[1] + f2.target[pair2] * lp.stride[2];
            const double* rowB = netB + pb1 * lb.stride[1] + pb2 * lb.stride[2];
            if (line0) {
              // A line's positions add: the product's row is contiguous.
              double* rowOut = out + base + pa0;
              for (int pb0 = 0; pb0 < f0.countB; ++pb0) rowOut[pb0] += scaled * (rowB[pb0] * weight0[pb0]);
            } else {
              for (int pb0 = 0; pb0 < f0.countB; ++pb0) out[base + target0[pb0]] += scaled * (rowB[pb0] * weight0[pb0]);
            }
          }
        }
      }
    }
  }
}

namespace {

/// The rule of DifferentiateNet: output coefficient c is
/// degree * (in[up[c]] - in[zero[c]]).
struct DerivativeRule {
  CellShape shape;        ///< Of the output.
  int degree = 0;         ///< The differentiated factor's degree.
  std::vector<int> up;    ///< Input position of beta + e_dir.
  std::vector<int> zero;  ///< Input position of beta + e_0.
};

DerivativeRule BuildDerivativeRule(const CellShape& shape, int factor, int dir) {
  std::array<int, kMaxFactors> degrees{};
  for (int f = 0; f < shape.numFactors(); ++f) degrees[f] = shape.factor(f).degree - (f == factor ? 1 : 0);
  DerivativeRule rule;
  rule.shape = CellShape(shape.type(), degrees);
  rule.degree = shape.factor(factor).degree;
  const NetLayout from(shape), to(rule.shape);
  const int nOut = NetSize(rule.shape);
  rule.up.resize(nOut);
  rule.zero.resize(nOut);
  // d/ds_dir B^p_{beta + .} sums: b'_beta = p (b_{beta + e_dir} - b_{beta + e_0}).
  for (int c = 0; c < nOut; ++c) {
    int base = 0;
    for (int f = 0; f < to.numFactors; ++f) {
      if (f != factor) base += to.Position(c, f) * from.stride[f];
    }
    const std::array<int, 4>& beta = to.index[factor]->multi(to.Position(c, factor));
    std::array<int, 4> up = beta, zero = beta;
    up[dir + 1] += 1;
    zero[0] += 1;
    const int stride = from.stride[factor];
    const SimplexIndex& index = *from.index[factor];
    rule.up[c] = base + index.Position(up) * stride;
    rule.zero[c] = base + index.Position(zero) * stride;
  }
  return rule;
}

}  // namespace

void DifferentiateNet(const CellShape& shape, int factor, int dir, const double* in, double* out,
                      CellShape* outShape) {
  const DerivativeRule rule = BuildDerivativeRule(shape, factor, dir);
  *outShape = rule.shape;
  const int p = rule.degree;
  for (std::size_t c = 0; c < rule.up.size(); ++c) out[c] = p * (in[rule.up[c]] - in[rule.zero[c]]);
}

const HessianStencil& HessianStencil::Get(const CellShape& shape) {
  // One stencil per (cell type, degrees); cells of the same shape share it.
  static std::mutex mutex;
  static std::map<std::array<int, 4>, std::unique_ptr<HessianStencil>> cache;
  const std::array<int, 4> key{static_cast<int>(shape.type()), shape.factor(0).degree,
                               shape.numFactors() > 1 ? shape.factor(1).degree : 0,
                               shape.numFactors() > 2 ? shape.factor(2).degree : 0};
  std::lock_guard<std::mutex> lock(mutex);
  std::unique_ptr<HessianStencil>& entry = cache[key];
  if (!entry) entry.reset(new HessianStencil(shape));
  return *entry;
}

HessianStencil::HessianStencil(const CellShape& shape) : paramDim_(shape.paramDim()) {
  int factorOf[3] = {0, 0, 0}, dirOf[3] = {0, 0, 0};
  for (int f = 0; f < shape.numFactors(); ++f) {
    for (int d = 0; d < shape.factor(f).dim; ++d) {
      factorOf[shape.factor(f).offset + d] = f;
      dirOf[shape.factor(f).offset + d] = d;
    }
  }
  // Each row composes the two differences' rules: at most
  // HessianRun::kMaxTerms terms, merged by input position (ascending) with
  // their integer weights summed and zeros dropped, as differentiating each
  // unit net twice gives them (which cost O(n^2): 28 s for the degree-16
  // nets of a degree-8 hex).
  for (int a = 0; a < paramDim_; ++a) {
    for (int b = a; b < paramDim_; ++b) {
      Entry& entry = entries_[a][b];
      const bool defined = shape.factor(factorOf[a]).degree >= 1 &&
                           shape.factor(factorOf[b]).degree >= (factorOf[a] == factorOf[b] ? 2 : 1);
      if (!defined) continue;  // identically zero: no rows
      const DerivativeRule first = BuildDerivativeRule(shape, factorOf[a], dirOf[a]);
      const DerivativeRule second = BuildDerivativeRule(first.shape, factorOf[b], dirOf[b]);
      const double p1 = first.degree, p2 = second.degree;
      std::vector<std::pair<int, double>> row;
      for (std::size_t r = 0; r < second.up.size(); ++r) {
        const std::pair<int, double> terms[4] = {{first.up[second.up[r]], p2 * p1},
                                                 {first.zero[second.up[r]], -(p2 * p1)},
                                                 {first.up[second.zero[r]], -(p2 * p1)},
                                                 {first.zero[second.zero[r]], p2 * p1}};
        row.assign(std::begin(terms), std::end(terms));
        std::sort(row.begin(), row.end());
        // Merge equal positions, then drop the terms that cancel.
        std::size_t kept = 0;
        for (std::size_t t = 0; t < row.size(); ++t) {
          if (kept > 0 && row[kept - 1].first == row[t].first) {
            row[kept - 1].second += row[t].second;
          } else {
            row[kept++] = row[t];
          }
        }
        row.resize(kept);
        row.erase(std::remove_if(row.begin(), row.end(), [](const auto& term) { return term.second == 0.0; }),
                  row.end());
        AppendRow(row, &entry.runs);
      }
    }
  }
}

bool HessianStencil::RowRange(const Entry& entry, const double* f, const NetNoise& noise, bool positive,
                              double* lo, double* hi) {
  double l = std::numeric_limits<double>::infinity(), h = -l, nonFinite = 0.0;
  for (const HessianRun& run : entry.runs) {
    if (noise.weights) {
      RunRange<0, true>(run, f, noise, &l, &h, &nonFinite);
    } else if (run.terms == 3) {
      RunRange<3, false>(run, f, noise, &l, &h, &nonFinite);
    } else if (run.terms == 4) {
      RunRange<4, false>(run, f, noise, &l, &h, &nonFinite);
    } else {
      RunRange<0, false>(run, f, noise, &l, &h, &nonFinite);
    }
    if (positive && l <= 0.0) return false;
  }
  if (nonFinite != 0.0) {
    // Some row is not a number: the entry is unbounded.
    l = -std::numeric_limits<double>::infinity();
    h = std::numeric_limits<double>::infinity();
    if (positive) return false;
  }
  *lo = l;
  *hi = h;
  return true;
}

bool HessianStencil::IsConvex(const double* f, const NetNoise& noise) const {
  double lo[3][3] = {}, hi[3][3] = {};
  // The diagonal first: a failing one ends the test before any mixed entry.
  for (int a = 0; a < paramDim_; ++a) {
    const Entry& entry = entries_[a][a];
    if (entry.runs.empty()) return false;  // not strictly convex along a
    if (!RowRange(entry, f, noise, true, &lo[a][a], &hi[a][a])) return false;
  }
  for (int a = 0; a < paramDim_; ++a) {
    for (int b = a + 1; b < paramDim_; ++b) {
      if (!entries_[a][b].runs.empty()) RowRange(entries_[a][b], f, noise, false, &lo[a][b], &hi[a][b]);
    }
  }
  return IntervalMatrixIsPositive(paramDim_, lo, hi);
}

void HessianStencil::HessianRanges(const double* f, double lo[3][3], double hi[3][3]) const {
  for (int a = 0; a < paramDim_; ++a) {
    for (int b = a; b < paramDim_; ++b) {
      lo[a][b] = hi[a][b] = 0.0;
      if (!entries_[a][b].runs.empty()) RowRange(entries_[a][b], f, NetNoise{}, false, &lo[a][b], &hi[a][b]);
    }
  }
}

}  // namespace invmap::kernels
