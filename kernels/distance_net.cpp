#include "kernels/distance_net.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

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

}  // namespace

void MultiplyNets(const CellShape& a, const double* netA, const CellShape& b, const double* netB, double* out) {
  std::array<int, kMaxFactors> degrees{};
  for (int f = 0; f < a.numFactors(); ++f) degrees[f] = a.factor(f).degree + b.factor(f).degree;
  const CellShape product(a.type(), degrees);
  const NetLayout la(a), lb(b), lp(product);
  std::fill(out, out + NetSize(product), 0.0);
  // B^p_alpha B^q_beta = C(alpha) C(beta) / C(alpha + beta) B^{p+q}_{alpha+beta}
  // per factor, with C the multinomial coefficients.
  for (int ia = 0; ia < NetSize(a); ++ia) {
    if (netA[ia] == 0.0) continue;
    for (int ib = 0; ib < NetSize(b); ++ib) {
      double coef = netA[ia] * netB[ib];
      int target = 0;
      for (int f = 0; f < la.numFactors; ++f) {
        const int pa = la.Position(ia, f), pb = lb.Position(ib, f);
        const std::array<int, 4>& ma = la.index[f]->multi(pa);
        const std::array<int, 4>& mb = lb.index[f]->multi(pb);
        const std::array<int, 4> sum{ma[0] + mb[0], ma[1] + mb[1], ma[2] + mb[2], ma[3] + mb[3]};
        const int ps = lp.index[f]->Position(sum);
        coef *= la.index[f]->multinomial(pa) * lb.index[f]->multinomial(pb) / lp.index[f]->multinomial(ps);
        target += ps * lp.stride[f];
      }
      out[target] += coef;
    }
  }
}

void SplitNet(const CellShape& shape, int factor, int i, int j, const double* in, double* out) {
  const NetLayout layout(shape);
  const SimplexIndex& index = *layout.index[factor];
  const int stride = layout.stride[factor];
  const int n = NetSize(shape);
  // Blossom of the net at the child's vertices, where vertex j is the
  // midpoint (e_i + e_j) / 2: expanding the alpha_j midpoint arguments gives
  // b'_alpha = sum_m C(alpha_j, m) 2^-alpha_j b_{alpha with (alpha_i + alpha_j - m) at i, m at j}.
  for (int c = 0; c < n; ++c) {
    const int pos = layout.Position(c, factor);
    const int base = c - pos * stride;
    const std::array<int, 4>& alpha = index.multi(pos);
    const int aj = alpha[j];
    std::array<int, 4> src = alpha;
    double sum = 0.0;
    const double scale = std::ldexp(1.0, -aj);
    for (int m = 0; m <= aj; ++m) {
      src[j] = m;
      src[i] = alpha[i] + aj - m;
      sum += Binomial(aj, m) * in[base + index.Position(src) * stride];
    }
    out[c] = sum * scale;
  }
}

void DifferentiateNet(const CellShape& shape, int factor, int dir, const double* in, double* out,
                      CellShape* outShape) {
  std::array<int, kMaxFactors> degrees{};
  for (int f = 0; f < shape.numFactors(); ++f) degrees[f] = shape.factor(f).degree - (f == factor ? 1 : 0);
  *outShape = CellShape(shape.type(), degrees);
  const NetLayout from(shape), to(*outShape);
  const int p = shape.factor(factor).degree;
  const int nOut = NetSize(*outShape);
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
    out[c] = p * (in[base + index.Position(up) * stride] - in[base + index.Position(zero) * stride]);
  }
}

void DistanceNets::Build(const CellView& cell, const double* center) {
  ambientDim_ = cell.ambientDim;
  rational_ = cell.weights != nullptr;
  const CellShape& base = cell.shape;
  shape_ = base.ScaledDegree(2);
  size_ = NetSize(shape_);
  for (int k = 0; k < 3; ++k) center_[k] = k < ambientDim_ ? center[k] : 0.0;

  const int n = base.numControlPoints();
  // Homogeneous translated control values: N_k = w (P_k - c_k), W = w.
  std::vector<double> homogeneous(static_cast<size_t>(n) * (ambientDim_ + 1));
  for (int c = 0; c < n; ++c) {
    const double w = rational_ ? cell.weights[c] : 1.0;
    for (int k = 0; k < ambientDim_; ++k) {
      homogeneous[static_cast<size_t>(k) * n + c] = w * (cell.points[static_cast<size_t>(c) * ambientDim_ + k] - center_[k]);
    }
    homogeneous[static_cast<size_t>(ambientDim_) * n + c] = w;
  }
  const double* weightNet = homogeneous.data() + static_cast<size_t>(ambientDim_) * n;

  nets_.assign(static_cast<size_t>(size_) * (ambientDim_ + 2), 0.0);
  std::vector<double> product(size_);
  double* nn = nets_.data();
  for (int k = 0; k < ambientDim_; ++k) {
    const double* nk = homogeneous.data() + static_cast<size_t>(k) * n;
    MultiplyNets(base, nk, base, nk, product.data());
    for (int i = 0; i < size_; ++i) nn[i] += product[i];
    MultiplyNets(base, nk, base, weightNet, nets_.data() + static_cast<size_t>(size_) * (k + 1));
  }
  MultiplyNets(base, weightNet, base, weightNet, nets_.data() + static_cast<size_t>(size_) * (ambientDim_ + 1));
  scale2_ = *std::max_element(nn, nn + size_);
}

void DistanceNets::SquaredDistanceNumerator(const double* point, double* q) const {
  double local[3] = {0, 0, 0};
  double local2 = 0.0;
  for (int k = 0; k < ambientDim_; ++k) {
    local[k] = point[k] - center_[k];
    local2 += local[k] * local[k];
  }
  const double* nn = nets_.data();
  const double* ww = this->ww();
  for (int i = 0; i < size_; ++i) q[i] = nn[i] + local2 * ww[i];
  for (int k = 0; k < ambientDim_; ++k) {
    const double* nw = nets_.data() + static_cast<size_t>(size_) * (k + 1);
    const double twoP = 2.0 * local[k];
    for (int i = 0; i < size_; ++i) q[i] -= twoP * nw[i];
  }
}

double DistanceNets::RoundingSlack(const double* point) const {
  double local2 = 0.0;
  for (int k = 0; k < ambientDim_; ++k) local2 += (point[k] - center_[k]) * (point[k] - center_[k]);
  const double* ww = this->ww();
  const double wwMax = *std::max_element(ww, ww + size_);
  const double magnitude = std::sqrt(scale2_) + std::sqrt(local2 * wwMax);
  // Each coefficient is a short sum of products of these magnitudes; the
  // subdivision steps are convex combinations and add rounding of the same order.
  return 64.0 * std::numeric_limits<double>::epsilon() * magnitude * magnitude;
}

double NetLowerBound(int size, const double* q, const double* ww) {
  double lb = std::numeric_limits<double>::infinity();
  if (ww) {
    for (int i = 0; i < size; ++i) lb = std::min(lb, q[i] / ww[i]);
  } else {
    for (int i = 0; i < size; ++i) lb = std::min(lb, q[i]);
  }
  return lb;
}

bool NetIsConvex(const CellShape& shape, const double* f, double* scratch) {
  const int pd = shape.paramDim();
  const int n = NetSize(shape);
  double* first = scratch;
  double* second = scratch + n;
  double lo[3][3], hi[3][3];
  // Parameter a of the cell is free coordinate dirOf[a] of factor factorOf[a].
  int factorOf[3], dirOf[3];
  for (int fac = 0; fac < shape.numFactors(); ++fac) {
    for (int d = 0; d < shape.factor(fac).dim; ++d) {
      factorOf[shape.factor(fac).offset + d] = fac;
      dirOf[shape.factor(fac).offset + d] = d;
    }
  }
  for (int a = 0; a < pd; ++a) {
    if (shape.factor(factorOf[a]).degree < 1) return false;  // constant along a: not strictly convex
    CellShape s1;
    DifferentiateNet(shape, factorOf[a], dirOf[a], f, first, &s1);
    for (int b = a; b < pd; ++b) {
      if (s1.factor(factorOf[b]).degree < 1) {
        if (a == b) return false;
        lo[a][b] = hi[a][b] = 0.0;
        continue;
      }
      CellShape s2;
      DifferentiateNet(s1, factorOf[b], dirOf[b], first, second, &s2);
      const int n2 = NetSize(s2);
      const auto range = std::minmax_element(second, second + n2);
      lo[a][b] = *range.first;
      hi[a][b] = *range.second;
    }
  }
  // Every Hessian in the box of intervals is mid + E with |E_ab| <= rad_ab,
  // so lambda_min >= lambda_min(mid) - ||rad||_F.
  Eigen::Matrix3d mid = Eigen::Matrix3d::Zero();
  double radius2 = 0.0;
  for (int a = 0; a < pd; ++a) {
    if (lo[a][a] <= 0.0) return false;
    for (int b = a; b < pd; ++b) {
      const double m = 0.5 * (lo[a][b] + hi[a][b]);
      const double r = 0.5 * (hi[a][b] - lo[a][b]);
      mid(a, b) = mid(b, a) = m;
      radius2 += (a == b ? 1.0 : 2.0) * r * r;
    }
  }
  if (pd == 1) return lo[0][0] > 0.0;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
  double lambdaMin;
  if (pd == 2) {
    const double tr = mid(0, 0) + mid(1, 1);
    const double det = mid(0, 0) * mid(1, 1) - mid(0, 1) * mid(0, 1);
    const double disc = std::sqrt(std::max(0.0, 0.25 * tr * tr - det));
    lambdaMin = 0.5 * tr - disc;
  } else {
    eigen.computeDirect(mid, Eigen::EigenvaluesOnly);
    lambdaMin = eigen.eigenvalues()(0);
  }
  return lambdaMin > std::sqrt(radius2);
}

}  // namespace invmap::kernels
