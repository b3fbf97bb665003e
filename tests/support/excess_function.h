// The function whose convexity and tangent planes the cell search relies
// on, from the reference evaluator: g(u) = W(u)^2 (|x(u) - p|^2 - level).
#pragma once

#include "tests/support/reference_cell.h"

namespace invmap::testing {

/// g(u) = W(u)^2 (|x(u) - p|^2 - level) of `cell` (W = 1 for a polynomial
/// cell), by RefEvaluate; W is the map of a polynomial copy of the cell
/// whose first coordinate holds the weights. Keeps references to the cell
/// and the point.
class ExcessFunction {
 public:
  ExcessFunction(const RefCell& cell, const double* point, double level);
  double operator()(const double* u) const;
  /// W(u).
  double Weight(const double* u) const;

 private:
  const RefCell& cell_;
  RefCell weightCell_;
  const double* point_;
  double level_;
};

}  // namespace invmap::testing
