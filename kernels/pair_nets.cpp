#include "kernels/pair_nets.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/bernstein_net.h"
#include "kernels/simplex_index.h"

namespace invmap::kernels {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Largest distance of a control point from `center` (model frame).
double ControlRadius(const CellView& cell, const double* center) {
  double radius2 = 0.0;
  for (int c = 0; c < cell.shape.numControlPoints(); ++c) {
    double r2 = 0.0;
    for (int k = 0; k < cell.ambientDim; ++k) {
      const double d = cell.points[static_cast<size_t>(c) * cell.ambientDim + k] - center[k];
      r2 += d * d;
    }
    radius2 = std::max(radius2, r2);
  }
  return std::sqrt(radius2);
}

/// Most tensor products in one joint net (the directional Hessians': four
/// groups of ambient dimension + 2).
constexpr int kMaxTerms = 4 * (kMaxDim + 2);

/// min and max over (i, j) of sum_t x[t][i] y[t][j]: the range of a joint
/// net held as a sum of `terms` tensor products. [-inf, inf] when some
/// coefficient is not finite. Row by row (a row of the joint net summed
/// term by term, which vectorizes along j); the sums are those of the
/// coefficient-by-coefficient order, bit for bit.
void ProductRange(int terms, const double* const* x, int nx, const double* const* y, int ny, double* lo,
                  double* hi) {
  constexpr int kRowOnStack = 512;
  double stackRow[kRowOnStack];
  std::vector<double> heapRow;
  double* row = stackRow;
  if (ny > kRowOnStack) {
    heapRow.resize(ny);
    row = heapRow.data();
  }
  double l = kInf, h = -kInf, check = 0.0;
  for (int i = 0; i < nx; ++i) {
    const double x0 = x[0][i];
    const double* y0 = y[0];
    for (int j = 0; j < ny; ++j) row[j] = x0 * y0[j];
    for (int t = 1; t < terms; ++t) {
      const double xt = x[t][i];
      const double* yt = y[t];
      for (int j = 0; j < ny; ++j) row[j] += xt * yt[j];
    }
    for (int j = 0; j < ny; ++j) {
      l = std::min(l, row[j]);
      h = std::max(h, row[j]);
      check += row[j] * 0.0;  // NaN once any coefficient is not finite
    }
  }
  if (check != 0.0 || !(l <= h)) {
    l = -kInf;
    h = kInf;
  }
  *lo = l;
  *hi = h;
}

/// An enclosure of ProductRange's range that reads each y net only through
/// its own range: sum_t x[t][i] y_t over every y_t in [min y[t], max y[t]],
/// independently per t. It loses what ties y's nets together, and costs
/// nx + ny coefficient reads instead of nx ny.
void BoxedRange(int terms, const double* const* x, int nx, const double* const* y, int ny, double* lo, double* hi) {
  double ylo[kMaxTerms], yhi[kMaxTerms];
  for (int t = 0; t < terms; ++t) {
    const auto [least, most] = std::minmax_element(y[t], y[t] + ny);
    ylo[t] = *least;
    yhi[t] = *most;
  }
  double l = kInf, h = -kInf, check = 0.0;
  for (int i = 0; i < nx; ++i) {
    double low = 0.0, high = 0.0;
    for (int t = 0; t < terms; ++t) {
      const double a = x[t][i] * ylo[t], b = x[t][i] * yhi[t];
      low += std::min(a, b);
      high += std::max(a, b);
    }
    l = std::min(l, low);
    h = std::max(h, high);
    check += (low + high) * 0.0;
  }
  if (check != 0.0 || !(l <= h)) {
    l = -kInf;
    h = kInf;
  }
  *lo = l;
  *hi = h;
}

/// The parameters of a cell shape as (factor, direction within the factor).
void ParameterFactors(const CellShape& shape, int* factor, int* dir) {
  for (int f = 0; f < shape.numFactors(); ++f) {
    for (int d = 0; d < shape.factor(f).dim; ++d) {
      factor[shape.factor(f).offset + d] = f;
      dir[shape.factor(f).offset + d] = d;
    }
  }
}

/// The derivative nets of `terms` nets of `shape` along parameter p (and,
/// with q >= 0, then along q): written to `out` (terms nets of *outSize
/// each); false when the derivative is identically zero (a factor of too
/// low a degree).
bool Derivatives(const CellShape& shape, int terms, const double* const* in, int p, int q, std::vector<double>* out,
                 int* outSize) {
  int factor[kMaxDim] = {0, 0, 0}, dir[kMaxDim] = {0, 0, 0};
  ParameterFactors(shape, factor, dir);
  if (shape.factor(factor[p]).degree < 1) return false;
  CellShape first;
  std::array<int, kMaxFactors> degrees{};
  for (int f = 0; f < shape.numFactors(); ++f) degrees[f] = shape.factor(f).degree - (f == factor[p] ? 1 : 0);
  first = CellShape(shape.type(), degrees);
  const int n1 = NetSize(first);
  if (q < 0) {
    out->resize(static_cast<size_t>(terms) * n1);
    CellShape ignored;
    for (int t = 0; t < terms; ++t) DifferentiateNet(shape, factor[p], dir[p], in[t], out->data() + t * n1, &ignored);
    *outSize = n1;
    return true;
  }
  if (first.factor(factor[q]).degree < 1) return false;
  std::vector<double> once(n1);
  CellShape second;
  degrees[factor[q]] -= 1;
  second = CellShape(shape.type(), degrees);
  const int n2 = NetSize(second);
  out->resize(static_cast<size_t>(terms) * n2);
  CellShape ignored;
  for (int t = 0; t < terms; ++t) {
    DifferentiateNet(shape, factor[p], dir[p], in[t], once.data(), &ignored);
    DifferentiateNet(first, factor[q], dir[q], once.data(), out->data() + t * n2, &ignored);
  }
  *outSize = n2;
  return true;
}

/// Per-factor basis sizes and strides of a net (first factor fastest).
struct Strides {
  int count[kMaxFactors] = {1, 1, 1};
  int stride[kMaxFactors] = {1, 1, 1};
  explicit Strides(const CellShape& shape) {
    int s = 1;
    for (int f = 0; f < shape.numFactors(); ++f) {
      count[f] = SimplexBasisSize(shape.factor(f).dim, shape.factor(f).degree);
      stride[f] = s;
      s *= count[f];
    }
  }
};

/// The same polynomial as `in` (on `shape`) with factor f's degree raised
/// by one: b'_alpha = sum_i alpha_i / (p + 1) b_{alpha - e_i}.
void ElevateNet(const CellShape& shape, int f, const double* in, double* out, CellShape* outShape) {
  std::array<int, kMaxFactors> degrees{};
  for (int g = 0; g < shape.numFactors(); ++g) degrees[g] = shape.factor(g).degree + (g == f ? 1 : 0);
  *outShape = CellShape(shape.type(), degrees);
  const Strides from(shape), to(*outShape);
  const SimplexFactor& factor = shape.factor(f);
  const SimplexIndex& lower = SimplexIndex::Get(factor.dim, factor.degree);
  const SimplexIndex& upper = SimplexIndex::Get(factor.dim, factor.degree + 1);
  const double inverse = 1.0 / (factor.degree + 1);
  const int nOut = NetSize(*outShape);
  for (int c = 0; c < nOut; ++c) {
    int base = 0;
    for (int g = 0; g < shape.numFactors(); ++g) {
      if (g != f) base += ((c / to.stride[g]) % to.count[g]) * from.stride[g];
    }
    const std::array<int, 4>& alpha = upper.multi((c / to.stride[f]) % to.count[f]);
    double sum = 0.0;
    for (int i = 0; i <= factor.dim; ++i) {
      if (alpha[i] == 0) continue;
      std::array<int, 4> down = alpha;
      --down[i];
      sum += alpha[i] * inverse * in[base + lower.Position(down) * from.stride[f]];
    }
    out[c] = sum;
  }
}

/// The derivative net of `in` along parameter p (then q, with q >= 0),
/// raised back to `shape`'s degrees: so every derivative of a side's nets
/// shares one index space and they can be combined coefficient by
/// coefficient. Zero when the derivative vanishes identically.
void FullShapeDerivative(const CellShape& shape, const double* in, int p, int q, double* out) {
  int factor[kMaxDim] = {0, 0, 0}, dir[kMaxDim] = {0, 0, 0};
  ParameterFactors(shape, factor, dir);
  const int n = NetSize(shape);
  const int needP = 1 + (q >= 0 && factor[q] == factor[p] ? 1 : 0);
  if (shape.factor(factor[p]).degree < needP || (q >= 0 && shape.factor(factor[q]).degree < 1)) {
    std::fill(out, out + n, 0.0);
    return;
  }
  std::vector<double> a(n), b(n);
  CellShape s1, s2;
  DifferentiateNet(shape, factor[p], dir[p], in, a.data(), &s1);
  if (q >= 0) {
    DifferentiateNet(s1, factor[q], dir[q], a.data(), b.data(), &s2);
    ElevateNet(s2, factor[q], b.data(), a.data(), &s1);
  }
  ElevateNet(s1, factor[p], a.data(), out, &s2);
}

/// g = Q - level WW of two sides' nets (each side: its net of |x|^2 w, its
/// d nets of x_k w, its net of w; na and nb coefficients each) as d + 2
/// separated terms alpha_t (x) beta_t:
///   (a_0 - level a_W) (x) b_W,  a_W (x) b_0,  a_k (x) (-2 b_k),
/// written to alpha (d + 2 nets of na) and beta (d + 2 nets of nb).
void SeparateTerms(const double* sideA, const double* sideB, int d, int na, int nb, double level, double* alpha,
                   double* beta) {
  const double* aw = sideA + (d + 1) * na;
  const double* bw = sideB + (d + 1) * nb;
  for (int i = 0; i < na; ++i) {
    alpha[i] = sideA[i] - level * aw[i];
    alpha[na + i] = aw[i];
  }
  for (int j = 0; j < nb; ++j) {
    beta[j] = bw[j];
    beta[nb + j] = sideB[j];
  }
  for (int k = 0; k < d; ++k) {
    std::copy(sideA + (1 + k) * na, sideA + (2 + k) * na, alpha + (2 + k) * na);
    for (int j = 0; j < nb; ++j) beta[(2 + k) * nb + j] = -2.0 * sideB[(1 + k) * nb + j];
  }
}

}  // namespace

PairNets::PairNets(const PairSide& a, const PairSide& b) {
  side_[0] = &a;
  side_[1] = &b;
  ambientDim_ = a.cell.ambientDim;
  terms_ = ambientDim_ + 2;
  double centers[2][3];
  double radius[2];
  for (int s = 0; s < 2; ++s) {
    const PairSide& side = *side_[s];
    shape_[s] = side.nets->shape();
    size_[s] = side.nets->size();
    rational_ = rational_ || side.nets->rational();
    for (int k = 0; k < 3; ++k) {
      for (int l = 0; l < 3; ++l) rotation_[s][k][l] = side.motion.rotation[k][l];
    }
    const double* c = side.nets->center();
    const double local[3] = {c[0], c[1], ambientDim_ > 2 ? c[2] : 0.0};
    side.motion.Apply(local, centers[s]);
    radius[s] = ControlRadius(side.cell, local);
  }
  double distance2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    offset_[k] = k < ambientDim_ ? centers[0][k] - centers[1][k] : 0.0;
    distance2 += offset_[k] * offset_[k];
  }
  // |d|^2 WW stays out of the nets (shift_): with it, every term of Q_ij
  // was of the order of |d|^2 and so was its rounding, which for models
  // farther apart than some hundred times their size exceeded the distance
  // tolerance (2 tau |d|) and no subdomain near the minimum could be
  // excluded. Without it, as DistanceNets::RoundingSlack argues for one
  // cell, every term is at most (R_a + R_b) (R_a + R_b + 2 |d|) WW_ij, and
  // so is its rounding (subdivisions are convex combinations and keep
  // that); adding |d|^2 back rounds once more.
  shift_ = distance2;
  const double radii = radius[0] + radius[1];
  const double eps = std::numeric_limits<double>::epsilon();
  slack_ = 128.0 * eps * radii * (radii + 2.0 * std::sqrt(distance2)) + 4.0 * eps * distance2;
}

void PairNets::BuildRoot(double* sideA, double* sideB) const {
  for (int s = 0; s < 2; ++s) Place(s, side_[s]->nets->nn(), s == 0 ? sideA : sideB);
}

void PairNets::BuildRootOwn(double* sideA, double* sideB) const {
  for (int s = 0; s < 2; ++s) {
    const DistanceNets& nets = *side_[s]->nets;
    std::copy(nets.nn(), nets.nn() + sideLength(s), s == 0 ? sideA : sideB);
  }
}

void PairNets::Place(int s, const double* own, double* out) const {
  const int d = ambientDim_;
  const int n = size_[s];
  // The vector nets turned into the common frame: NW_k = sum_l R_kl NW_l.
  for (int k = 0; k < d; ++k) {
    double* nw = out + (1 + k) * n;
    std::fill(nw, nw + n, 0.0);
    for (int l = 0; l < d; ++l) {
      const double r = rotation_[s][k][l];
      if (r == 0.0) continue;
      const double* source = own + (1 + l) * n;
      for (int i = 0; i < n; ++i) nw[i] += r * source[i];
    }
  }
  std::copy(own + (d + 1) * n, own + (d + 2) * n, out + (d + 1) * n);
  const double* nn = own;
  double* zero = out;
  const double sign = s == 0 ? 2.0 : -2.0;
  for (int i = 0; i < n; ++i) {
    double v = nn[i];
    for (int k = 0; k < d; ++k) v += sign * offset_[k] * out[(1 + k) * n + i];
    zero[i] = v;
  }
}

void PairNets::Split(int side, int factor, int vi, int vj, const double* in, double* out) const {
  const int n = size_[side];
  for (int t = 0; t < terms_; ++t) SplitNet(shape_[side], factor, vi, vj, in + t * n, out + t * n);
}

double PairNets::LowerBound(const double* sideA, const double* sideB, std::vector<double>* scratch, int* argA,
                            int* argB) const {
  const int d = ambientDim_;
  const int na = size_[0], nb = size_[1];
  // Quotients by the weights, per side: Q_ij / WW_ij = A0_i + B0_j - 2 sum_k Ak_i Bk_j.
  if (scratch->size() < static_cast<size_t>((d + 1) * (na + nb))) scratch->resize((d + 1) * (na + nb));
  double* qa = scratch->data();
  double* qb = qa + (d + 1) * na;
  const double* wa = sideA + (d + 1) * na;
  const double* wb = sideB + (d + 1) * nb;
  for (int t = 0; t <= d; ++t) {
    const double factor = t == 0 ? 1.0 : -2.0;  // the -2 of the cross terms goes to A's side
    for (int i = 0; i < na; ++i) qa[t * na + i] = factor * (rational_ ? sideA[t * na + i] / wa[i] : sideA[t * na + i]);
    for (int j = 0; j < nb; ++j) qb[t * nb + j] = rational_ ? sideB[t * nb + j] / wb[j] : sideB[t * nb + j];
  }
  double least = kInf;
  int bestA = 0, bestB = 0;
  for (int i = 0; i < na; ++i) {
    const double a0 = qa[i];
    const double a1 = qa[na + i], a2 = qa[2 * na + i];
    const double a3 = d > 2 ? qa[3 * na + i] : 0.0;
    const double* b0 = qb;
    const double* b1 = qb + nb;
    const double* b2 = qb + 2 * nb;
    double rowLeast = kInf;
    if (d > 2) {
      const double* b3 = qb + 3 * nb;
      for (int j = 0; j < nb; ++j) rowLeast = std::min(rowLeast, a0 + b0[j] + a1 * b1[j] + a2 * b2[j] + a3 * b3[j]);
    } else {
      for (int j = 0; j < nb; ++j) rowLeast = std::min(rowLeast, a0 + b0[j] + a1 * b1[j] + a2 * b2[j]);
    }
    if (rowLeast < least) {
      least = rowLeast;
      bestA = i;
    }
  }
  // The boxes of the subdomains' control points, which hold them: a
  // rational net of the doubled degree has control points NW_i / WW_i and
  // weights WW_i. Where the joint net's bound is poor (a valley of equal
  // distances running diagonally across the joint parameters, where each
  // side's coefficients pair with far-off ones of the other), the boxes
  // still separate the parts of the pair that lie far apart.
  double boxGap2 = 0.0;
  for (int k = 0; k < d; ++k) {
    const double* pa = qa + (1 + k) * na;  // -2 x_k, relative to A's net centre
    const double* pb = qb + (1 + k) * nb;  // y_k, relative to B's
    double loA = kInf, hiA = -kInf, loB = kInf, hiB = -kInf;
    for (int i = 0; i < na; ++i) {
      loA = std::min(loA, -0.5 * pa[i]);
      hiA = std::max(hiA, -0.5 * pa[i]);
    }
    for (int j = 0; j < nb; ++j) {
      loB = std::min(loB, pb[j]);
      hiB = std::max(hiB, pb[j]);
    }
    const double gap = std::max({loA + offset_[k] - hiB, 0.0, loB - (hiA + offset_[k])});
    boxGap2 += gap * gap;
  }
  // Rounded down a little: the box coordinates carry their own rounding.
  least = std::max(least + shift_, boxGap2 * (1.0 - 1e-12));
  if (argA || argB) {
    // The row's column, found again (the loop above keeps only the value,
    // which vectorizes).
    const double a0 = qa[bestA], a1 = qa[na + bestA], a2 = qa[2 * na + bestA];
    const double a3 = d > 2 ? qa[3 * na + bestA] : 0.0;
    double rowLeast = kInf;
    for (int j = 0; j < nb; ++j) {
      const double v = a0 + qb[j] + a1 * qb[nb + j] + a2 * qb[2 * nb + j] + (d > 2 ? a3 * qb[3 * nb + j] : 0.0);
      if (v < rowLeast) {
        rowLeast = v;
        bestB = j;
      }
    }
    if (argA) *argA = bestA;
    if (argB) *argB = bestB;
  }
  return least;
}

double PairNets::UpperBound(const double* sideA, const double* sideB) const {
  const int d = ambientDim_;
  const int na = size_[0], nb = size_[1];
  double most = -kInf;
  for (int i = 0; i < na; ++i) {
    for (int j = 0; j < nb; ++j) {
      double q = sideA[i] * sideB[(d + 1) * nb + j] + sideA[(d + 1) * na + i] * sideB[j];
      for (int k = 0; k < d; ++k) q -= 2.0 * sideA[(1 + k) * na + i] * sideB[(1 + k) * nb + j];
      most = std::max(most, q / (sideA[(d + 1) * na + i] * sideB[(d + 1) * nb + j]));
    }
  }
  return most + shift_;
}

double PairNets::LeastWeight(const double* sideA, const double* sideB) const {
  if (!rational_) return 1.0;
  const int d = ambientDim_;
  const double* wa = sideA + (d + 1) * size_[0];
  const double* wb = sideB + (d + 1) * size_[1];
  return *std::min_element(wa, wa + size_[0]) * *std::min_element(wb, wb + size_[1]);
}

double PairNets::LargestWeight(const double* sideA, const double* sideB) const {
  if (!rational_) return 1.0;
  const int d = ambientDim_;
  const double* wa = sideA + (d + 1) * size_[0];
  const double* wb = sideB + (d + 1) * size_[1];
  return *std::max_element(wa, wa + size_[0]) * *std::max_element(wb, wb + size_[1]);
}

void PairNets::HessianRanges(const double* sideA, const double* sideB, double level, bool boxed, double* lo,
                             double* hi, std::vector<double>* scratch) const {
  const int d = ambientDim_;
  const int na = size_[0], nb = size_[1];
  const int pa = shape_[0].paramDim(), pb = shape_[1].paramDim();
  const int n = pa + pb;
  // g = Q - level WW as d + 2 separated terms (SeparateTerms).
  const int terms = d + 2;
  scratch->resize(static_cast<size_t>(terms) * (na + nb));
  double* alpha = scratch->data();
  double* beta = alpha + terms * na;
  SeparateTerms(sideA, sideB, d, na, nb, level - shift_, alpha, beta);
  const double* alphaNets[8];
  const double* betaNets[8];
  for (int t = 0; t < terms; ++t) {
    alphaNets[t] = alpha + t * na;
    betaNets[t] = beta + t * nb;
  }
  std::fill(lo, lo + n * n, 0.0);
  std::fill(hi, hi + n * n, 0.0);
  auto set = [&](int r, int c, double l, double h) {
    lo[r * n + c] = lo[c * n + r] = l;
    hi[r * n + c] = hi[c * n + r] = h;
  };
  // First derivatives per parameter, kept for the mixed entries.
  std::vector<double> firstA[kMaxDim], firstB[kMaxDim];
  int sizeA1[kMaxDim] = {}, sizeB1[kMaxDim] = {};
  bool hasA1[kMaxDim] = {}, hasB1[kMaxDim] = {};
  for (int p = 0; p < pa; ++p) hasA1[p] = Derivatives(shape_[0], terms, alphaNets, p, -1, &firstA[p], &sizeA1[p]);
  for (int p = 0; p < pb; ++p) hasB1[p] = Derivatives(shape_[1], terms, betaNets, p, -1, &firstB[p], &sizeB1[p]);
  std::vector<double> second;
  const double* x[8];
  const double* y[8];
  int size2 = 0;
  for (int p = 0; p < pa; ++p) {
    for (int q = p; q < pa; ++q) {
      if (!Derivatives(shape_[0], terms, alphaNets, p, q, &second, &size2)) continue;
      for (int t = 0; t < terms; ++t) x[t] = second.data() + t * size2;
      double l, h;
      (boxed ? BoxedRange : ProductRange)(terms, x, size2, betaNets, nb, &l, &h);
      set(p, q, l, h);
    }
  }
  for (int p = 0; p < pb; ++p) {
    for (int q = p; q < pb; ++q) {
      if (!Derivatives(shape_[1], terms, betaNets, p, q, &second, &size2)) continue;
      for (int t = 0; t < terms; ++t) y[t] = second.data() + t * size2;
      double l, h;
      (boxed ? BoxedRange : ProductRange)(terms, y, size2, alphaNets, na, &l, &h);
      set(pa + p, pa + q, l, h);
    }
  }
  for (int p = 0; p < pa; ++p) {
    if (!hasA1[p]) continue;
    for (int t = 0; t < terms; ++t) x[t] = firstA[p].data() + t * sizeA1[p];
    for (int q = 0; q < pb; ++q) {
      if (!hasB1[q]) continue;
      for (int t = 0; t < terms; ++t) y[t] = firstB[q].data() + t * sizeB1[q];
      double l, h;
      (boxed ? BoxedRange : ProductRange)(terms, x, sizeA1[p], y, sizeB1[q], &l, &h);
      set(p, pa + q, l, h);
    }
  }
}

bool PairNets::MostBentEdgeAt(const double* sideA, const double* sideB, int argA, int argB, int* side,
                              int* factor, int* vi, int* vj) const {
  const int d = ambientDim_;
  const int na = size_[0], nb = size_[1];
  // Q_ij / WW_ij of one coefficient of the joint net.
  auto quotient = [&](int i, int j) {
    double q = sideA[i] * sideB[(d + 1) * nb + j] + sideA[(d + 1) * na + i] * sideB[j];
    for (int k = 0; k < d; ++k) q -= 2.0 * sideA[(1 + k) * na + i] * sideB[(1 + k) * nb + j];
    return q / (sideA[(d + 1) * na + i] * sideB[(d + 1) * nb + j]);
  };
  const double center = quotient(argA, argB);
  double most = 0.0;
  for (int s = 0; s < 2; ++s) {
    const CellShape& shape = shape_[s];
    const Strides strides(shape);
    const int at = s == 0 ? argA : argB;
    for (int f = 0; f < shape.numFactors(); ++f) {
      const SimplexFactor& fac = shape.factor(f);
      const SimplexIndex& index = SimplexIndex::Get(fac.dim, fac.degree);
      const int position = (at / strides.stride[f]) % strides.count[f];
      const int base = at - position * strides.stride[f];
      const std::array<int, 4>& alpha = index.multi(position);
      for (int i = 0; i <= fac.dim; ++i) {
        for (int j = i + 1; j <= fac.dim; ++j) {
          // Three coefficients in a row along the edge: one unit moved from
          // barycentric index i to j (delta) and back, through this one, or
          // shifted inward where it sits on the net's boundary.
          std::array<int, 4> step = alpha;
          bool shifted = false;
          if (alpha[i] == 0 && alpha[j] >= 2) {
            ++step[i];
            --step[j];
            shifted = true;
          } else if (alpha[j] == 0 && alpha[i] >= 2) {
            --step[i];
            ++step[j];
            shifted = true;
          } else if (alpha[i] == 0 || alpha[j] == 0) {
            continue;
          }
          std::array<int, 4> lower = step, upper = step;
          --lower[i];
          ++lower[j];
          ++upper[i];
          --upper[j];
          auto coefficient = [&](const std::array<int, 4>& m) { return base + index.Position(m) * strides.stride[f]; };
          const int mid = coefficient(step), low = coefficient(lower), high = coefficient(upper);
          const double vm = !shifted ? center : (s == 0 ? quotient(mid, argB) : quotient(argA, mid));
          const double vl = s == 0 ? quotient(low, argB) : quotient(argA, low);
          const double vh = s == 0 ? quotient(high, argB) : quotient(argA, high);
          const double bend = std::abs(vl - 2.0 * vm + vh);
          if (bend > most) {
            most = bend;
            *side = s;
            *factor = f;
            *vi = i;
            *vj = j;
          }
        }
      }
    }
  }
  return most > 0.0;
}

void PairNets::GradientRanges(const double* sideA, const double* sideB, double level, double* lo, double* hi,
                              std::vector<double>* scratch) const {
  const int d = ambientDim_;
  const int na = size_[0], nb = size_[1];
  const int pa = shape_[0].paramDim(), pb = shape_[1].paramDim();
  const int terms = d + 2;
  scratch->resize(static_cast<size_t>(terms) * (na + nb));
  double* alpha = scratch->data();
  double* beta = alpha + terms * na;
  SeparateTerms(sideA, sideB, d, na, nb, level - shift_, alpha, beta);
  const double* alphaNets[8];
  const double* betaNets[8];
  for (int t = 0; t < terms; ++t) {
    alphaNets[t] = alpha + t * na;
    betaNets[t] = beta + t * nb;
  }
  std::vector<double> first;
  const double* x[8];
  int size1 = 0;
  for (int p = 0; p < pa + pb; ++p) {
    lo[p] = hi[p] = 0.0;
    const int side = p < pa ? 0 : 1;
    const int q = side == 0 ? p : p - pa;
    if (!Derivatives(shape_[side], terms, side == 0 ? alphaNets : betaNets, q, -1, &first, &size1)) continue;
    for (int t = 0; t < terms; ++t) x[t] = first.data() + t * size1;
    if (side == 0) {
      ProductRange(terms, x, size1, betaNets, nb, &lo[p], &hi[p]);
    } else {
      ProductRange(terms, alphaNets, na, x, size1, &lo[p], &hi[p]);
    }
  }
}

void PairNets::HessianRangesInBasis(const double* sideA, const double* sideB, double level, const double* basis,
                                    double* lo, double* hi, std::vector<double>* scratch) const {
  const int d = ambientDim_;
  const int na = size_[0], nb = size_[1];
  const int pa = shape_[0].paramDim(), pb = shape_[1].paramDim();
  const int n = pa + pb;
  const int terms = d + 2;
  // The terms of g as in HessianRanges, then every first and second
  // derivative of every term on its side's full shape.
  const int firstCount = terms * (pa * na + pb * nb);
  const int secondCount = terms * (pa * pa * na + pb * pb * nb);
  scratch->assign(static_cast<size_t>(terms) * (na + nb) + firstCount + secondCount + 8 * static_cast<size_t>(terms) * (na + nb), 0.0);
  double* alpha = scratch->data();
  double* beta = alpha + terms * na;
  SeparateTerms(sideA, sideB, d, na, nb, level - shift_, alpha, beta);
  double* firstA = beta + terms * nb;                 // [p][t][i]
  double* firstB = firstA + terms * pa * na;          // [p][t][j]
  double* secondA = firstB + terms * pb * nb;         // [p][q][t][i]
  double* secondB = secondA + terms * pa * pa * na;   // [p][q][t][j]
  double* work = secondB + terms * pb * pb * nb;
  for (int t = 0; t < terms; ++t) {
    for (int p = 0; p < pa; ++p) {
      FullShapeDerivative(shape_[0], alpha + t * na, p, -1, firstA + (p * terms + t) * na);
      for (int q = p; q < pa; ++q) {
        FullShapeDerivative(shape_[0], alpha + t * na, p, q, secondA + ((p * pa + q) * terms + t) * na);
        if (q != p) {
          std::copy(secondA + ((p * pa + q) * terms + t) * na, secondA + ((p * pa + q) * terms + t + 1) * na,
                    secondA + ((q * pa + p) * terms + t) * na);
        }
      }
    }
    for (int p = 0; p < pb; ++p) {
      FullShapeDerivative(shape_[1], beta + t * nb, p, -1, firstB + (p * terms + t) * nb);
      for (int q = p; q < pb; ++q) {
        FullShapeDerivative(shape_[1], beta + t * nb, p, q, secondB + ((p * pb + q) * terms + t) * nb);
        if (q != p) {
          std::copy(secondB + ((p * pb + q) * terms + t) * nb, secondB + ((p * pb + q) * terms + t + 1) * nb,
                    secondB + ((q * pb + p) * terms + t) * nb);
        }
      }
    }
  }
  // Per pair of basis vectors (u, w): u^T H w = sum_t [ (uA^T D2 alpha_t wA) (x) beta_t
  //   + (uA . D alpha_t) (x) (wB . D beta_t) + (wA . D alpha_t) (x) (uB . D beta_t)
  //   + alpha_t (x) (uB^T D2 beta_t wB) ].
  double* xa = work;                        // 3 groups of terms nets on A
  double* yb = xa + 3 * terms * na;         // 3 groups on B
  const double* x[kMaxTerms];
  const double* y[kMaxTerms];
  for (int r = 0; r < n; ++r) {
    const double* u = basis + r * n;
    for (int c = r; c < n; ++c) {
      const double* w = basis + c * n;
      std::fill(xa, xa + 3 * terms * na + 3 * terms * nb, 0.0);
      for (int t = 0; t < terms; ++t) {
        double* second = xa + t * na;
        double* firstU = xa + (terms + t) * na;
        double* firstW = xa + (2 * terms + t) * na;
        for (int p = 0; p < pa; ++p) {
          for (int q = 0; q < pa; ++q) {
            const double weight = u[p] * w[q];
            if (weight == 0.0) continue;
            const double* net = secondA + ((p * pa + q) * terms + t) * na;
            for (int i = 0; i < na; ++i) second[i] += weight * net[i];
          }
          const double* net = firstA + (p * terms + t) * na;
          for (int i = 0; i < na; ++i) {
            firstU[i] += u[p] * net[i];
            firstW[i] += w[p] * net[i];
          }
        }
        double* secondOnB = yb + t * nb;
        double* firstWB = yb + (terms + t) * nb;
        double* firstUB = yb + (2 * terms + t) * nb;
        for (int p = 0; p < pb; ++p) {
          for (int q = 0; q < pb; ++q) {
            const double weight = u[pa + p] * w[pa + q];
            if (weight == 0.0) continue;
            const double* net = secondB + ((p * pb + q) * terms + t) * nb;
            for (int j = 0; j < nb; ++j) secondOnB[j] += weight * net[j];
          }
          const double* net = firstB + (p * terms + t) * nb;
          for (int j = 0; j < nb; ++j) {
            firstWB[j] += w[pa + p] * net[j];
            firstUB[j] += u[pa + p] * net[j];
          }
        }
        x[t] = second;
        y[t] = beta + t * nb;
        x[terms + t] = firstU;
        y[terms + t] = firstWB;
        x[2 * terms + t] = firstW;
        y[2 * terms + t] = firstUB;
        x[3 * terms + t] = alpha + t * na;
        y[3 * terms + t] = secondOnB;
      }
      double l, h;
      ProductRange(4 * terms, x, na, y, nb, &l, &h);
      lo[r * n + c] = lo[c * n + r] = l;
      hi[r * n + c] = hi[c * n + r] = h;
    }
  }
}

}  // namespace invmap::kernels
