// A quick convexity proof for the squared distance from a point to a
// polynomial cell, from bounds over the cell that are computed once.
#pragma once

#include "kernels/bernstein_net.h"
#include "kernels/distance_net.h"

namespace invmap::kernels {

/// For a polynomial cell and a point p, half the Hessian of
/// f(u) = |x(u) - p|^2 is
///   x_a . x_b + (x - c) . x_ab  -  (p - c) . x_ab
/// for any fixed c (the cell's center). The first part, half the Hessian
/// of |x - c|^2, does not depend on p: the second-derivative nets of the NN
/// net of DistanceNets bound it over the cell. The second
/// is bounded per point by the box of x_ab's net coefficients, written as
/// its midpoint m and radius r: (p - c) . x_ab lies within
/// (p - c) . m -+ |p - c| r. Every Hessian then lies in an interval matrix
/// that IntervalMatrixIsPositive may prove positive definite. A little
/// looser than the test on the net of f itself (HessianStencil::IsConvex),
/// but a few operations per point instead of a pass over a net of twice
/// the cell's degree.
class CurvatureBounds {
 public:
  /// `nets`: the cell's DistanceNets (built around the center c);
  /// `stencil`: the HessianStencil of their shape. Rational cells, and cells
  /// with a factor of degree 0 (constant along it), get bounds that prove
  /// nothing.
  CurvatureBounds(const CellView& cell, const DistanceNets& nets, const HessianStencil& stencil);

  /// True when |x(u) - point|^2 is strictly convex over the whole cell.
  bool ProvesConvex(const double* point) const;

 private:
  static constexpr int kEntries = 6;  ///< (a, b) with a <= b < 3, at Entry(a, b).
  static int Entry(int a, int b) { return a * (5 - a) / 2 + b; }

  bool available_ = false;
  int paramDim_ = 0;
  int ambientDim_ = 3;
  double center_[3] = {0, 0, 0};
  double fixedLo_[kEntries] = {};   ///< Lower bound of x_a . x_b + (x - c) . x_ab.
  double fixedHi_[kEntries] = {};   ///< Upper bound of the same.
  double midpoint_[kEntries][3] = {};  ///< Midpoint m of the box of x_ab's coefficients.
  double radius_[kEntries] = {};       ///< Largest |coefficient - m| of x_ab's net.
};

}  // namespace invmap::kernels
