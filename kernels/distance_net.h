// Scalar Bernstein nets on a cell's reference domain, and the nets of the
// squared distance from a query point to a cell, which bound it from below.
#pragma once

#include <vector>

#include "kernels/bernstein_net.h"
#include "kernels/cell_map.h"

#include <cstddef>

namespace invmap::kernels {

/// Point-independent parts of the squared distance from a point to a cell.
///
/// With the cell written homogeneously as x(u) = N(u) / W(u) and everything
/// translated to the cell's center c, the squared distance to p is
///   f(u) = q(u) / W(u)^2,  q = |N - (p - c) W|^2 = NN - 2 (p - c).NW + |p - c|^2 WW,
/// where NN = |N|^2, NW = N W and WW = W^2 are nets of twice the cell's
/// degree. Since WW's coefficients are positive, min_i q_i / WW_i bounds f
/// from below on the whole cell, exactly so when f is constant.
class DistanceNets {
 public:
  /// Precomputes NN, NW and WW for `cell`, translated to `center`.
  void Build(const CellView& cell, const double* center);

  /// Shape of the nets (the cell's degrees doubled).
  const CellShape& shape() const { return shape_; }
  int size() const { return size_; }
  /// True for rational cells; polynomial cells have WW = 1.
  bool rational() const { return rational_; }
  /// The center the nets are built around (ambient coordinates).
  const double* center() const { return center_; }
  /// The NN net (size() values): |x - center|^2 for a polynomial cell.
  const double* nn() const { return nets_.data(); }
  /// The NW net of ambient coordinate k (size() values): x_k - center_k for
  /// a polynomial cell.
  const double* nw(int k) const { return nets_.data() + static_cast<size_t>(size_) * (k + 1); }
  /// Ambient dimension of the cell.
  int ambientDim() const { return ambientDim_; }
  /// The WW net (size() values).
  const double* ww() const { return nets_.data() + static_cast<size_t>(size_) * (ambientDim_ + 1); }
  /// Writes the q net of `point` (size() values).
  void SquaredDistanceNumerator(const double* point, double* q) const;
  /// Heap memory of the nets, in bytes.
  std::size_t MemoryBytes() const { return nets_.capacity() * sizeof(double); }
  /// Magnitude of the rounding error of the quotients q_i / WW_i (squared
  /// distance units) for `point`, after any number of subdivisions.
  double RoundingSlack(const double* point) const;

 private:
  CellShape shape_;
  int size_ = 0;
  int ambientDim_ = 3;
  bool rational_ = false;
  double center_[3] = {0, 0, 0};
  // For the slack: the largest distance of a control point from the center.
  double radius_ = 0.0;
  std::vector<double> nets_;  // NN, NW_0 .. NW_{dim-1}, WW: size_ values each
};

/// Lower bound of q / WW over the domain of the nets: min_i q_i / ww_i, or
/// min_i q_i when ww is null (polynomial cell).
double NetLowerBound(int size, const double* q, const double* ww);

}  // namespace invmap::kernels
