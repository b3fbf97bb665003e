#include "kernels/curvature_bounds.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "kernels/interval_matrix.h"

namespace invmap::kernels {

CurvatureBounds::CurvatureBounds(const CellView& cell, const DistanceNets& nets, const HessianStencil& stencil)
    : paramDim_(cell.shape.paramDim()), ambientDim_(cell.ambientDim) {
  const CellShape& shape = cell.shape;
  const int ad = ambientDim_;
  if (cell.weights != nullptr) return;
  int factorOf[3] = {0, 0, 0}, dirOf[3] = {0, 0, 0};
  for (int f = 0; f < shape.numFactors(); ++f) {
    if (shape.factor(f).degree < 1) return;
    for (int d = 0; d < shape.factor(f).dim; ++d) {
      factorOf[shape.factor(f).offset + d] = f;
      dirOf[shape.factor(f).offset + d] = d;
    }
  }
  // The fixed part: half the Hessian of |x - c|^2, whose net is NN.
  double lo[3][3], hi[3][3];
  stencil.HessianRanges(nets.nn(), lo, hi);
  double largest = 0.0;
  for (int a = 0; a < paramDim_; ++a) {
    for (int b = a; b < paramDim_; ++b) {
      fixedLo_[Entry(a, b)] = 0.5 * lo[a][b];
      fixedHi_[Entry(a, b)] = 0.5 * hi[a][b];
      largest = std::max({largest, std::abs(lo[a][b]), std::abs(hi[a][b])});
    }
  }
  // The box of each x_ab's net, from the coordinates' nets differentiated twice.
  const int n = shape.numControlPoints();
  std::vector<double> coordinate(n), first(n), second[3];
  for (int a = 0; a < paramDim_; ++a) {
    for (int b = a; b < paramDim_; ++b) {
      const int e = Entry(a, b);
      CellShape firstShape, secondShape;
      const bool sameFactor = factorOf[a] == factorOf[b];
      // x_ab is identically zero when the factor's degree leaves no second derivative.
      if (sameFactor && shape.factor(factorOf[a]).degree < 2) continue;
      for (int k = 0; k < ad; ++k) {
        for (int c = 0; c < n; ++c) coordinate[c] = cell.points[static_cast<size_t>(c) * ad + k];
        DifferentiateNet(shape, factorOf[a], dirOf[a], coordinate.data(), first.data(), &firstShape);
        second[k].resize(n);
        DifferentiateNet(firstShape, factorOf[b], dirOf[b], first.data(), second[k].data(), &secondShape);
      }
      const int secondSize = NetSize(secondShape);
      for (int k = 0; k < ad; ++k) {
        const auto [least, most] = std::minmax_element(second[k].begin(), second[k].begin() + secondSize);
        midpoint_[e][k] = 0.5 * (*least + *most);
      }
      double radius2 = 0.0;
      for (int i = 0; i < secondSize; ++i) {
        double d2 = 0.0;
        for (int k = 0; k < ad; ++k) d2 += (second[k][i] - midpoint_[e][k]) * (second[k][i] - midpoint_[e][k]);
        radius2 = std::max(radius2, d2);
      }
      radius_[e] = std::sqrt(radius2);
    }
  }
  for (int k = 0; k < ad; ++k) center_[k] = nets.center()[k];
  // The nets' coefficients carry rounding of the products and differences:
  // the bounds are widened well beyond it.
  const double widen = 1e-12 * largest;
  for (int e = 0; e < kEntries; ++e) {
    fixedLo_[e] -= widen;
    fixedHi_[e] += widen;
    radius_[e] *= 1.0 + 1e-12;
  }
  available_ = std::isfinite(largest);
}

bool CurvatureBounds::ProvesConvex(const double* point) const {
  if (!available_) return false;
  double d[3] = {0, 0, 0}, distance2 = 0.0;
  for (int k = 0; k < ambientDim_; ++k) {
    d[k] = point[k] - center_[k];
    distance2 += d[k] * d[k];
  }
  const double distance = std::sqrt(distance2);
  double lo[3][3] = {}, hi[3][3] = {};
  for (int a = 0; a < paramDim_; ++a) {
    for (int b = a; b < paramDim_; ++b) {
      const int e = Entry(a, b);
      double along = 0.0, size = 0.0;
      for (int k = 0; k < ambientDim_; ++k) {
        along += d[k] * midpoint_[e][k];
        size += std::abs(d[k] * midpoint_[e][k]);
      }
      // The dot product's rounding, and the spread of x_ab around m.
      const double spread = distance * radius_[e] + 1e-14 * size;
      lo[a][b] = fixedLo_[e] - along - spread;
      hi[a][b] = fixedHi_[e] - along + spread;
    }
  }
  return IntervalMatrixIsPositive(paramDim_, lo, hi);
}

}  // namespace invmap::kernels
