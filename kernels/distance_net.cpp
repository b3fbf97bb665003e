#include "kernels/distance_net.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/range_fold.h"
#include "kernels/simplex_index.h"
#include "kernels/tolerances.h"

namespace invmap::kernels {
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
  radius_ = 0.0;
  for (int c = 0; c < n; ++c) {
    double r2 = 0.0;
    for (int k = 0; k < ambientDim_; ++k) {
      const double d = cell.points[static_cast<size_t>(c) * ambientDim_ + k] - center_[k];
      r2 += d * d;
    }
    radius_ = std::max(radius_, std::sqrt(r2));
  }
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
  const double* nw[3] = {nullptr, nullptr, nullptr};
  double twoP[3] = {0, 0, 0};
  for (int k = 0; k < ambientDim_; ++k) {
    nw[k] = nets_.data() + static_cast<size_t>(size_) * (k + 1);
    twoP[k] = 2.0 * local[k];
  }
  // One pass, subtracting the coordinates' terms in order k = 0, 1, 2.
  if (ambientDim_ == 3) {
    for (int i = 0; i < size_; ++i) {
      q[i] = nn[i] + local2 * ww[i] - twoP[0] * nw[0][i] - twoP[1] * nw[1][i] - twoP[2] * nw[2][i];
    }
    return;
  }
  for (int i = 0; i < size_; ++i) {
    double v = nn[i] + local2 * ww[i];
    for (int k = 0; k < ambientDim_; ++k) v -= twoP[k] * nw[k][i];
    q[i] = v;
  }
}

double DistanceNets::RoundingSlack(const double* point) const {
  double local2 = 0.0;
  for (int k = 0; k < ambientDim_; ++k) local2 += (point[k] - center_[k]) * (point[k] - center_[k]);
  // The coefficients' products all have positive factors (Bernstein
  // coefficients, weights), so |NN_i| <= R^2 WW_i and |NW_i| <= R WW_i for
  // the control points' radius R: each term of q_i, and its rounding, is at
  // most (R + |p - c|)^2 WW_i, whatever the weights. The subdivision steps are
  // convex combinations of q and WW alike and keep that. Divided by WW_i, the
  // quotients' rounding does not grow with the weights' range (a slack in
  // units of q did: weights of 1e15 made it 1e16, and no part of the cell
  // could ever be excluded).
  const double magnitude = radius_ + std::sqrt(local2);
  return kNetRounding * magnitude * magnitude;
}

double NetLowerBound(int size, const double* q, const double* ww) {
  double lb = std::numeric_limits<double>::infinity();
  if (!ww) return FoldMin(size, q, lb);
  // The quotients in blocks first: a loop of divisions alone vectorizes.
  constexpr int kBlock = 64;
  double ratio[kBlock];
  for (int first = 0; first < size; first += kBlock) {
    const int count = std::min(kBlock, size - first);
    for (int i = 0; i < count; ++i) ratio[i] = q[first + i] / ww[first + i];
    lb = FoldMin(count, ratio, lb);
  }
  return lb;
}

}  // namespace invmap::kernels
