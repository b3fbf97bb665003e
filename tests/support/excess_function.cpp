#include "tests/support/excess_function.h"

namespace invmap::testing {

ExcessFunction::ExcessFunction(const RefCell& cell, const double* point, double level)
    : cell_(cell), weightCell_(cell), point_(point), level_(level) {
  weightCell_.weights.clear();
  for (int i = 0; i < cell.numControlPoints(); ++i) {
    for (int k = 0; k < cell.ambientDim; ++k) {
      weightCell_.points[i * cell.ambientDim + k] = k == 0 ? (cell.isRational() ? cell.weights[i] : 1.0) : 0.0;
    }
  }
}

double ExcessFunction::Weight(const double* u) const {
  double w[3];
  RefEvaluate(weightCell_, u, w);
  return w[0];
}

double ExcessFunction::operator()(const double* u) const {
  double x[3];
  RefEvaluate(cell_, u, x);
  double f = 0.0;
  for (int k = 0; k < cell_.ambientDim; ++k) f += (x[k] - point_[k]) * (x[k] - point_[k]);
  const double w = Weight(u);
  return w * w * (f - level_);
}

}  // namespace invmap::testing
