#include "kernels/pair_taylor_bounds.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "kernels/bernstein_net.h"
#include "kernels/cell_bounds.h"

namespace invmap::kernels {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

/// Rounding a net's coefficients carry from its subdivisions (each a convex
/// combination), in units of its largest coefficient: generous for the
/// deepest search (kMaxDepth splits of nets up to kMaxNetDegree).
constexpr double kNetRounding = 64.0 * 16.0 * kEps;

/// A linear map between nets as sparse rows: out[i] = sum over
/// [start[i], start[i + 1]) of weight * in[source].
struct SparseMap {
  std::vector<int> start{0};
  std::vector<int> source;
  std::vector<double> weight;
  int outSize() const { return static_cast<int>(start.size()) - 1; }
  void Apply(const double* in, double* out) const {
    for (int i = 0; i < outSize(); ++i) {
      double sum = 0.0;
      for (int e = start[i]; e < start[i + 1]; ++e) sum += weight[e] * in[source[e]];
      out[i] = sum;
    }
  }
};

/// The least-squares plane through a net's control values at their lattice
/// places (reference coordinates alpha / degree, as offsets from the
/// domain's centroid): plane slope g = sum_i coefficient[i] value_i.
struct PlaneFit {
  int size = 0;
  int paramDim = 0;
  std::vector<double> offset;       ///< size x paramDim.
  std::vector<double> coefficient;  ///< size x paramDim.
};

PlaneFit BuildPlaneFit(const CellShape& shape) {
  PlaneFit fit;
  fit.size = NetSize(shape);
  fit.paramDim = shape.paramDim();
  const int m = fit.size, pd = fit.paramDim;
  fit.offset.assign(static_cast<size_t>(m) * pd, 0.0);
  fit.coefficient.assign(static_cast<size_t>(m) * pd, 0.0);
  double centroid[3] = {0, 0, 0};
  bool varies[3] = {false, false, false};
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& fac = shape.factor(f);
    for (int i = 0; i < fac.dim; ++i) {
      centroid[fac.offset + i] = 1.0 / (fac.dim + 1);
      varies[fac.offset + i] = fac.degree > 0;
    }
  }
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (int c = 0; c < m; ++c) {
    double place[3] = {0, 0, 0};
    ControlPointLocation(shape, c, place);
    for (int p = 0; p < pd; ++p) fit.offset[c * pd + p] = varies[p] ? place[p] - centroid[p] : 0.0;
    for (int p = 0; p < pd; ++p) {
      for (int q = 0; q < pd; ++q) covariance(p, q) += fit.offset[c * pd + p] * fit.offset[c * pd + q];
    }
  }
  for (int p = 0; p < pd; ++p) {
    if (!varies[p]) covariance(p, p) = 1.0;  // its offsets are 0: the slope stays 0
  }
  for (int p = pd; p < 3; ++p) covariance(p, p) = 1.0;
  const Eigen::Matrix3d inverse = covariance.inverse();
  for (int c = 0; c < m; ++c) {
    for (int p = 0; p < pd; ++p) {
      double sum = 0.0;
      for (int q = 0; q < pd; ++q) sum += inverse(p, q) * fit.offset[c * pd + q];
      fit.coefficient[c * pd + p] = sum;
    }
  }
  return fit;
}

/// Everything the Taylor models need of one net shape, built once per shape.
struct ShapePlan {
  int paramDim = 0;
  int degree = 0;  ///< The largest factor degree.
  PlaneFit value;
  SparseMap first[3];
  PlaneFit firstFit[3];
  SparseMap second[3][3];  ///< p <= q.
  PlaneFit secondFit[3][3];
};

/// The derivative of a net along parameter p, as a sparse map (zero rows
/// when the factor's degree is 0).
SparseMap DerivativeMap(const CellShape& shape, int p, CellShape* outShape) {
  int factor = 0, dir = 0;
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& fac = shape.factor(f);
    if (p >= fac.offset && p < fac.offset + fac.dim) {
      factor = f;
      dir = p - fac.offset;
    }
  }
  SparseMap map;
  const int n = NetSize(shape);
  if (shape.factor(factor).degree < 1) {
    *outShape = shape;
    map.start.assign(n + 1, 0);
    return map;
  }
  std::array<int, kMaxFactors> degrees{};
  for (int f = 0; f < shape.numFactors(); ++f) degrees[f] = shape.factor(f).degree - (f == factor ? 1 : 0);
  *outShape = CellShape(shape.type(), degrees);
  const int m = NetSize(*outShape);
  std::vector<std::vector<std::pair<int, double>>> rows(m);
  std::vector<double> unit(n, 0.0), out(m);
  for (int s = 0; s < n; ++s) {
    unit[s] = 1.0;
    CellShape ignored;
    DifferentiateNet(shape, factor, dir, unit.data(), out.data(), &ignored);
    unit[s] = 0.0;
    for (int r = 0; r < m; ++r) {
      if (out[r] != 0.0) rows[r].emplace_back(s, out[r]);
    }
  }
  for (const auto& row : rows) {
    for (const auto& [source, weight] : row) {
      map.source.push_back(source);
      map.weight.push_back(weight);
    }
    map.start.push_back(static_cast<int>(map.source.size()));
  }
  return map;
}

SparseMap Compose(const SparseMap& outer, const SparseMap& inner) {
  SparseMap map;
  for (int i = 0; i < outer.outSize(); ++i) {
    std::map<int, double> row;
    for (int e = outer.start[i]; e < outer.start[i + 1]; ++e) {
      const int mid = outer.source[e];
      for (int f = inner.start[mid]; f < inner.start[mid + 1]; ++f) row[inner.source[f]] += outer.weight[e] * inner.weight[f];
    }
    for (const auto& [source, weight] : row) {
      if (weight == 0.0) continue;
      map.source.push_back(source);
      map.weight.push_back(weight);
    }
    map.start.push_back(static_cast<int>(map.source.size()));
  }
  return map;
}

const ShapePlan& PlanOf(const CellShape& shape) {
  static std::mutex mutex;
  static std::map<std::array<int, 4>, std::unique_ptr<ShapePlan>> cache;
  const std::array<int, 4> key{static_cast<int>(shape.type()), shape.factor(0).degree,
                               shape.numFactors() > 1 ? shape.factor(1).degree : 0,
                               shape.numFactors() > 2 ? shape.factor(2).degree : 0};
  std::lock_guard<std::mutex> lock(mutex);
  std::unique_ptr<ShapePlan>& entry = cache[key];
  if (entry) return *entry;
  entry = std::make_unique<ShapePlan>();
  ShapePlan& plan = *entry;
  plan.paramDim = shape.paramDim();
  for (int f = 0; f < shape.numFactors(); ++f) plan.degree = std::max(plan.degree, shape.factor(f).degree);
  plan.value = BuildPlaneFit(shape);
  CellShape firstShape[3];
  for (int p = 0; p < plan.paramDim; ++p) {
    plan.first[p] = DerivativeMap(shape, p, &firstShape[p]);
    plan.firstFit[p] = BuildPlaneFit(firstShape[p]);
  }
  for (int p = 0; p < plan.paramDim; ++p) {
    for (int q = p; q < plan.paramDim; ++q) {
      CellShape secondShape;
      const SparseMap along = DerivativeMap(firstShape[p], q, &secondShape);
      plan.second[p][q] = Compose(along, plan.first[p]);
      if (plan.first[p].source.empty()) plan.second[p][q].start.assign(NetSize(secondShape) + 1, 0);
      plan.secondFit[p][q] = BuildPlaneFit(secondShape);
    }
  }
  return plan;
}

}  // namespace

PairTaylorBounds::PairTaylorBounds(const PairNets& nets, const double* sideA, const double* sideB) {
  ambientDim_ = nets.terms() - 2;
  paramDim_[0] = nets.shape(0).paramDim();
  paramDim_[1] = nets.shape(1).paramDim();
  n_ = paramDim_[0] + paramDim_[1];
  for (int s = 0; s < 2; ++s) {
    const CellShape& shape = nets.shape(s);
    const int offset = s == 0 ? 0 : paramDim_[0];
    for (int f = 0; f < shape.numFactors(); ++f) {
      const SimplexFactor& fac = shape.factor(f);
      for (int i = 0; i < fac.dim; ++i) {
        factorFirst_[offset + fac.offset + i] = offset + fac.offset;
        factorDim_[offset + fac.offset + i] = fac.dim;
      }
    }
  }
  valid_ = BuildSide(nets, 0, sideA) && BuildSide(nets, 1, sideB);
  if (!valid_) return;
  for (int k = 0; k < ambientDim_; ++k) {
    Affine& z = z_[k];
    const Affine& x = side_[0].x[k];
    const Affine& y = side_[1].x[k];
    z.c = nets.offset()[k] + x.c - y.c;
    for (int i = 0; i < n_; ++i) z.g[i] = x.g[i] - y.g[i];
    z.r = x.r + y.r + 4.0 * kEps * (std::abs(nets.offset()[k]) + std::abs(x.c) + std::abs(y.c));
  }
}

void PairTaylorBounds::LinearRange(const Affine& a, double* lo, double* hi) const {
  double l = 0.0, h = 0.0;
  for (int i = 0; i < n_;) {
    const int dim = factorDim_[i];
    if (dim == 1) {
      // s in [-1/2, 1/2].
      l -= 0.5 * std::abs(a.g[i]);
      h += 0.5 * std::abs(a.g[i]);
      ++i;
      continue;
    }
    // The simplex's vertices, as offsets from its centroid: -1/(d+1) in
    // every coordinate, plus 1 in one of them (or none).
    double base = 0.0;
    for (int j = 0; j < dim; ++j) base -= a.g[i + j] / (dim + 1);
    double least = base, most = base;
    for (int j = 0; j < dim; ++j) {
      least = std::min(least, base + a.g[i + j]);
      most = std::max(most, base + a.g[i + j]);
    }
    l += least;
    h += most;
    i += dim;
  }
  *lo = l;
  *hi = h;
}

double PairTaylorBounds::LinearRadius(const Affine& a) const {
  double lo, hi;
  LinearRange(a, &lo, &hi);
  return std::max(-lo, hi);
}

PairTaylorBounds::Affine PairTaylorBounds::Multiply(const Affine& a, const Affine& b) const {
  Affine out;
  const double ra = LinearRadius(a), rb = LinearRadius(b);
  out.c = a.c * b.c;
  double magnitude = std::abs(out.c);
  for (int i = 0; i < n_; ++i) {
    out.g[i] = a.c * b.g[i] + b.c * a.g[i];
    magnitude += std::abs(out.g[i]);
  }
  // The product of the linear parts, and every term with a remainder.
  out.r = ra * rb + (std::abs(a.c) + ra) * b.r + (std::abs(b.c) + rb) * a.r + a.r * b.r;
  out.r += 8.0 * kEps * (magnitude + out.r);
  return out;
}

void PairTaylorBounds::Range(const Affine& a, double* lo, double* hi) const {
  double l, h;
  LinearRange(a, &l, &h);
  *lo = a.c + l - a.r;
  *hi = a.c + h + a.r;
}

bool PairTaylorBounds::BuildSide(const PairNets& nets, int s, const double* values) {
  const CellShape& shape = nets.shape(s);
  const ShapePlan& plan = PlanOf(shape);
  const int m = NetSize(shape);
  const int d = ambientDim_;
  const int pd = plan.paramDim;
  const int offset = s == 0 ? 0 : paramDim_[0];
  const double* ww = values + (d + 1) * m;
  const bool rational = nets.rational(s);
  Side& side = side_[s];

  // The affine model of the net `net` (m' values) of a fitted shape, its
  // remainder grown by the rounding of `order` differences of a net whose
  // largest coefficient is `magnitude`.
  auto model = [&](const PlaneFit& fit, const double* net, int order, double magnitude) {
    Affine a;
    double mean = 0.0;
    for (int i = 0; i < fit.size; ++i) mean += net[i];
    a.c = mean / fit.size;
    double slope[3] = {0, 0, 0};
    for (int i = 0; i < fit.size; ++i) {
      for (int p = 0; p < pd; ++p) slope[p] += fit.coefficient[i * pd + p] * net[i];
    }
    double remainder = 0.0;
    for (int i = 0; i < fit.size; ++i) {
      double v = net[i] - a.c;
      for (int p = 0; p < pd; ++p) v -= slope[p] * fit.offset[i * pd + p];
      remainder = std::max(remainder, std::abs(v));
    }
    for (int p = 0; p < pd; ++p) a.g[offset + p] = slope[p];
    const double growth = std::pow(2.0 * plan.degree + 2.0, order);
    a.r = remainder + kNetRounding * growth * magnitude + 16.0 * kEps * (std::abs(a.c) + remainder);
    return a;
  };

  std::vector<double> derivative;
  // Nets 0 .. d-1: NW_k; net d: WW (ones for a polynomial side).
  Affine value[4], first[4][3], second[4][3][3];
  for (int t = 0; t <= d; ++t) {
    if (t == d && !rational) break;
    const double* net = t < d ? values + (1 + t) * m : ww;
    double magnitude = 0.0;
    for (int i = 0; i < m; ++i) magnitude = std::max(magnitude, std::abs(net[i]));
    if (!std::isfinite(magnitude)) return false;
    value[t] = model(plan.value, net, 0, magnitude);
    for (int p = 0; p < pd; ++p) {
      derivative.resize(plan.first[p].outSize());
      plan.first[p].Apply(net, derivative.data());
      first[t][p] = model(plan.firstFit[p], derivative.data(), 1, magnitude);
    }
    for (int p = 0; p < pd; ++p) {
      for (int q = p; q < pd; ++q) {
        derivative.resize(plan.second[p][q].outSize());
        plan.second[p][q].Apply(net, derivative.data());
        second[t][p][q] = second[t][q][p] = model(plan.secondFit[p][q], derivative.data(), 2, magnitude);
      }
    }
  }
  if (!rational) {
    for (int k = 0; k < d; ++k) {
      side.x[k] = value[k];
      for (int p = 0; p < pd; ++p) {
        side.d1[k][p] = first[k][p];
        for (int q = 0; q < pd; ++q) side.d2[k][p][q] = second[k][p][q];
      }
    }
    return true;
  }
  // The quotient rule on x = N / W (N = NW_k, W = WW) in affine arithmetic:
  //   x_p = (N_p - x W_p) / W,  x_pq = (N_pq - x_p W_q - x_q W_p - x W_pq) / W.
  // 1 / W on W's range [a, b] (a > 0): the line of slope -1 / b^2 through
  // the middle of 1/w + w / b^2's range, off by at most (b - a)^2 / (2 a b^2).
  double wLo, wHi;
  Range(value[d], &wLo, &wHi);
  const auto [leastWeight, mostWeight] = std::minmax_element(ww, ww + m);
  wLo = std::max(wLo, *leastWeight);
  wHi = std::min(wHi, *mostWeight);
  if (!(wLo > 0.0) || !(wHi >= wLo) || !std::isfinite(wHi)) return false;
  const double slope = -1.0 / (wHi * wHi);
  const double top = 1.0 / wLo - slope * wLo, bottom = 2.0 / wHi;
  Affine inverse;
  inverse.c = slope * value[d].c + 0.5 * (top + bottom);
  for (int i = 0; i < n_; ++i) inverse.g[i] = slope * value[d].g[i];
  inverse.r = std::abs(slope) * value[d].r + 0.5 * (top - bottom) + 8.0 * kEps * (std::abs(inverse.c) + top);
  auto subtract = [&](Affine a, const Affine& b) {
    a.c -= b.c;
    for (int i = 0; i < n_; ++i) a.g[i] -= b.g[i];
    a.r += b.r + 4.0 * kEps * (std::abs(a.c) + std::abs(b.c));
    return a;
  };
  for (int k = 0; k < d; ++k) {
    side.x[k] = Multiply(value[k], inverse);
    for (int p = 0; p < pd; ++p) {
      side.d1[k][p] = Multiply(subtract(first[k][p], Multiply(side.x[k], first[d][p])), inverse);
    }
    for (int p = 0; p < pd; ++p) {
      for (int q = p; q < pd; ++q) {
        Affine numerator = subtract(second[k][p][q], Multiply(side.d1[k][p], first[d][q]));
        numerator = subtract(numerator, Multiply(side.d1[k][q], first[d][p]));
        numerator = subtract(numerator, Multiply(side.x[k], second[d][p][q]));
        side.d2[k][p][q] = side.d2[k][q][p] = Multiply(numerator, inverse);
      }
    }
  }
  for (int k = 0; k < d; ++k) {
    if (!std::isfinite(side.x[k].r)) return false;
    for (int p = 0; p < pd; ++p) {
      if (!std::isfinite(side.d1[k][p].r)) return false;
      for (int q = 0; q < pd; ++q) {
        if (!std::isfinite(side.d2[k][p][q].r)) return false;
      }
    }
  }
  return true;
}

bool PairTaylorBounds::HessianBounds(const double* basis, double* lo, double* hi) const {
  if (!valid_) return false;
  const int n = n_, pa = paramDim_[0], pb = paramDim_[1], d = ambientDim_;
  auto direction = [&](int r, int i) { return basis ? basis[r * n + i] : (r == i ? 1.0 : 0.0); };
  // J u_r = Jx uA - Jy uB for every basis vector: a linear combination of
  // affine models, exact but for its rounding.
  auto combine = [&](double weight, const Affine& a, Affine* sum, double* magnitude) {
    sum->c += weight * a.c;
    for (int i = 0; i < n; ++i) sum->g[i] += weight * a.g[i];
    sum->r += std::abs(weight) * a.r;
    *magnitude += std::abs(weight) * (std::abs(a.c) + a.r);
  };
  Affine image[kMaxPairParams][3];
  for (int r = 0; r < n; ++r) {
    for (int k = 0; k < d; ++k) {
      Affine sum;
      double magnitude = 0.0;
      for (int p = 0; p < pa; ++p) combine(direction(r, p), side_[0].d1[k][p], &sum, &magnitude);
      for (int p = 0; p < pb; ++p) combine(-direction(r, pa + p), side_[1].d1[k][p], &sum, &magnitude);
      sum.r += 8.0 * kEps * magnitude;
      image[r][k] = sum;
    }
  }
  for (int r = 0; r < n; ++r) {
    for (int c = r; c < n; ++c) {
      double low = 0.0, high = 0.0;
      for (int k = 0; k < d; ++k) {
        double l, h;
        Range(Multiply(image[r][k], image[c][k]), &l, &h);
        if (r == c) l = std::max(l, 0.0);  // a square
        low += l;
        high += h;
        Affine curvature;
        double magnitude = 0.0;
        for (int p = 0; p < pa; ++p) {
          for (int q = 0; q < pa; ++q) combine(direction(r, p) * direction(c, q), side_[0].d2[k][p][q], &curvature, &magnitude);
        }
        for (int p = 0; p < pb; ++p) {
          for (int q = 0; q < pb; ++q) {
            combine(-direction(r, pa + p) * direction(c, pa + q), side_[1].d2[k][p][q], &curvature, &magnitude);
          }
        }
        curvature.r += 8.0 * kEps * magnitude;
        Range(Multiply(z_[k], curvature), &l, &h);
        low += l;
        high += h;
      }
      const double rounding = 8.0 * kEps * (std::abs(low) + std::abs(high));
      low = 2.0 * (low - rounding);
      high = 2.0 * (high + rounding);
      if (!std::isfinite(low) || !std::isfinite(high)) return false;
      lo[r * n + c] = lo[c * n + r] = low;
      hi[r * n + c] = hi[c * n + r] = high;
    }
  }
  return true;
}

}  // namespace invmap::kernels
