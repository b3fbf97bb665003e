// Squared distances from a point to axis-aligned boxes: the lower bounds the
// searches prune cells and BVH nodes with.
#pragma once

#include <algorithm>

#include "engine/bvh_build.h"
#include "kernels/cell_solver.h"

namespace invmap::engine {

/// Distance from x to the interval [lo, hi] along one axis.
inline double AxisGap(double lo, double x, double hi) { return std::max({lo - x, 0.0, x - hi}); }

/// Squared distance from a point to the box [lo, hi].
inline double BoxDistance2(const double* lo, const double* hi, const double* p, int dim) {
  double d2 = 0.0;
  for (int k = 0; k < dim; ++k) {
    const double d = AxisGap(lo[k], p[k], hi[k]);
    d2 += d * d;
  }
  return d2;
}

inline double BoxDistance2(const BvhBox& box, const double* p, int dim) { return BoxDistance2(box.lo, box.hi, p, dim); }

/// Squared distance from a point to a cell's control-point box.
inline double CellBoxDistance2(const kernels::CellSolver& solver, const double* p, int dim) {
  return BoxDistance2(solver.boxLo(), solver.boxHi(), p, dim);
}

}  // namespace invmap::engine
