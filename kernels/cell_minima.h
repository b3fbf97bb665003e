// Every local minimum of the distance from a point to ONE cell, certified:
// a branch and bound over subdomains that drops a subdomain when its
// Bernstein bound lies beyond the distance asked for, or when the distance
// changes monotonically along a direction that leaves no point of the
// subdomain stuck on the cell's boundary (no minimum can lie there), and
// settles it when the distance is convex enough to hold at most one
// minimum, which a local solve over the subdomain then finds.
#pragma once

#include <vector>

#include "kernels/cell_solver.h"

namespace invmap::kernels {

/// One local minimum of |x(u) - p| over a cell's domain.
struct CellMinimum {
  double ref[3] = {0, 0, 0};      ///< Reference coordinates (paramDim used).
  double closest[3] = {0, 0, 0};  ///< x(ref).
  double distance = 0.0;
};

struct CellMinimaResult {
  std::vector<CellMinimum> minima;  ///< In no particular order; a minimum on an edge of two subdomains may repeat.
  /// False when the search ran out of its budget (a continuum of minima,
  /// such as a circle of them seen from a torus's axis, has no isolated ones).
  bool certified = true;
};

/// Scratch of CellLocalMinima; one per thread.
struct MinimaWorkspace {
  std::vector<double> slots;
  std::vector<int> stack;
  std::vector<double> scratch;
};

/// The local minima of the distance from `point` to the cell of `solver`
/// not farther than `maxDistance`: points of the domain where the distance
/// is least over a neighbourhood in the domain (a minimum on the domain's
/// boundary counts; whether it is a minimum of a whole model whose cells
/// meet there is the caller's question).
CellMinimaResult CellLocalMinima(const CellSolver& solver, const double* point, double maxDistance,
                                 MinimaWorkspace* ws);

}  // namespace invmap::kernels
