#include "tests/support/bspline_reference.h"

#include <cstddef>

namespace invmap::testing {

std::vector<double> CoxDeBoorBasis(const std::vector<double>& knots, int degree, int span,
                                   double t) {
  const int numKnots = static_cast<int>(knots.size());
  std::vector<double> n(numKnots - 1, 0.0);
  n[span] = 1.0;
  for (int k = 1; k <= degree; ++k) {
    for (int i = 0; i + k + 1 < numKnots; ++i) {
      double value = 0.0;
      const double left = knots[i + k] - knots[i];
      if (left > 0.0) value += (t - knots[i]) / left * n[i];
      const double right = knots[i + k + 1] - knots[i + 1];
      if (right > 0.0) value += (knots[i + k + 1] - t) / right * n[i + 1];
      n[i] = value;
    }
  }
  n.resize(numKnots - degree - 1);
  return n;
}

void EvaluateBSplinePatch(const engine::BSplinePatch& patch, const int* spans, const double* params,
                          double* out) {
  const int paramDim = static_cast<int>(patch.degrees.size());
  std::vector<double> basis[3] = {{1.0}, {1.0}, {1.0}};
  for (int d = 0; d < paramDim; ++d) {
    basis[d] = CoxDeBoorBasis(patch.knots[d], patch.degrees[d], spans[d], params[d]);
  }
  const int dim = patch.ambientDim;
  const bool rational = !patch.weights.empty();
  double sum[4] = {0.0, 0.0, 0.0, 0.0};
  std::size_t point = 0;
  for (double nw : basis[2]) {
    for (double nv : basis[1]) {
      for (double nu : basis[0]) {
        const double w = rational ? patch.weights[point] : 1.0;
        const double b = nu * nv * nw * w;
        for (int d = 0; d < dim; ++d) sum[d] += b * patch.controlPoints[point * dim + d];
        sum[3] += b;
        ++point;
      }
    }
  }
  for (int d = 0; d < dim; ++d) out[d] = rational ? sum[d] / sum[3] : sum[d];
}

}  // namespace invmap::testing
