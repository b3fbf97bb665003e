// A quick convexity proof for the squared distance from a point to a cell,
// from bounds over the cell that are computed once.
#pragma once

#include "kernels/bernstein_net.h"
#include "kernels/distance_net.h"

namespace invmap::kernels {

/// With the nets of DistanceNets around the center c and d = p - c, the
/// function whose convexity the cell search needs is
///   g = q - level WW = NN - 2 d . NW + (|d|^2 - level) WW
/// (for a polynomial cell, WW = 1 and g = |x - p|^2 - level). Each Hessian
/// entry of g is the matching combination of the Hessians of NN, NW_k and
/// WW, whose ranges over the cell (their second-derivative nets'
/// coefficients) do not depend on p: they are computed once, and per point
/// the combination of ranges gives an interval matrix holding every Hessian
/// of g, which IntervalMatrixIsPositive may prove positive definite. A
/// little looser than the test on the net of g itself
/// (HessianStencil::IsConvex), but a few operations per point instead of a
/// net of twice the cell's degree.
class CurvatureBounds {
 public:
  /// `stencil`: the HessianStencil of the nets' shape.
  CurvatureBounds(const DistanceNets& nets, const HessianStencil& stencil);

  /// True when g = q - level WW of `point` is strictly convex over the
  /// whole cell.
  bool ProvesConvex(const double* point, double level) const;

 private:
  /// ProvesConvex for many points at once (kernels/newton_lanes.h).
  friend struct CurvatureLanes;

  static constexpr int kEntries = 6;  ///< (a, b) with a <= b < 3, at Entry(a, b).
  static int Entry(int a, int b) { return a * (5 - a) / 2 + b; }

  /// The range [lo, hi] of one Hessian entry of one net over the cell.
  struct Range {
    double lo = 0.0, hi = 0.0;
    double mid() const { return 0.5 * (lo + hi); }
    double radius() const { return 0.5 * (hi - lo); }
  };

  int paramDim_ = 0;
  int ambientDim_ = 3;
  bool rational_ = false;
  double center_[3] = {0, 0, 0};
  Range nn_[kEntries];
  Range nw_[kEntries][3];
  Range ww_[kEntries];  ///< Zero for a polynomial cell.
};

}  // namespace invmap::kernels
