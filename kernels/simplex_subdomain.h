// The subdomains of the branch and bound searches (of one cell and of a
// pair of cells) are products of simplices, one per simplex factor, each
// given by its d + 1 vertices in the factor's reference coordinates.
#pragma once

#include <Eigen/Dense>

#include "kernels/tolerances.h"

namespace invmap::kernels {

/// True when `ref` (the factor's d coordinates, d = 1, 2 or 3) lies in the
/// simplex with vertices vertex(0) .. vertex(d), up to kInsideTolerance in
/// its barycentric coordinates.
template <typename VertexOf>
bool InSimplexSubdomain(int d, const double* ref, VertexOf&& vertex) {
  const double* v0 = vertex(0);
  if (d == 1) {
    // An interval: the quotient the factorization below would compute,
    // without setting it up (line, quad and hex factors).
    const double mu = (ref[0] - v0[0]) / (vertex(1)[0] - v0[0]);
    return !(mu < -kInsideTolerance || 1.0 - mu < -kInsideTolerance);
  }
  Eigen::Matrix3d edges = Eigen::Matrix3d::Identity();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (int k = 1; k <= d; ++k) {
    for (int i = 0; i < d; ++i) edges(i, k - 1) = vertex(k)[i] - v0[i];
  }
  for (int i = 0; i < d; ++i) rhs[i] = ref[i] - v0[i];
  // The identity pads the unused dimensions: a fixed-size solve, no heap.
  const Eigen::Vector3d mu = edges.partialPivLu().solve(rhs);
  double sum = 0.0;
  for (int k = 0; k < d; ++k) {
    if (mu[k] < -kInsideTolerance) return false;
    sum += mu[k];
  }
  return !(1.0 - sum < -kInsideTolerance);
}

}  // namespace invmap::kernels
