#include "kernels/distance_net.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/simplex_index.h"

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

}  // namespace invmap::kernels
