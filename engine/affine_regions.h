// Affine regions (section 7.3.2.2 and algorithm 6 of the inverse-mapping
// chapter): blocks of adjacent cells of one B-spline patch that share a
// single affine map from the patch's parameters, x = A u + b. A region is
// searched as one block: the closest point of an affine map over a parameter
// box is a small convex problem solved exactly, whatever the number of cells
// it spans, so a flat plate or a uniformly parametrized block volume costs
// one solve instead of one per cell near the point.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/bezier_nets.h"
#include "kernels/cell_solver.h"

namespace invmap::engine {

/// A block of cells [spanLo, spanLo + spanCount) per direction of a patch's
/// cell grid, all affine with one map x = A u + b over the knot box [lo, hi].
struct AffineRegion {
  int paramDim = 0;
  int ambientDim = 0;
  double lo[3] = {0, 0, 0};  ///< Parameter box (knot values).
  double hi[3] = {0, 0, 0};
  double A[3][3] = {};       ///< A[k][d] = dx_k / du_d.
  double b[3] = {0, 0, 0};
  /// Global index of the region's first cell and the index step of one span
  /// in each direction.
  std::int64_t firstCell = 0;
  std::int64_t cellStride[3] = {0, 0, 0};
  /// Knot values bounding the region's spans, spanCount[d] + 1 per direction.
  std::vector<double> breaks[3];
  double boxLo[3] = {0, 0, 0};  ///< Bounds of the region's cells.
  double boxHi[3] = {0, 0, 0};

  std::int64_t numCells() const;
};

/// The closest point of a region to a query point.
struct RegionSolution {
  double u[3] = {0, 0, 0};        ///< Patch parameters of the closest point.
  double closest[3] = {0, 0, 0};  ///< A u + b.
  double distance = 0;
  std::int64_t cell = 0;          ///< Global index of the cell holding u.
  double ref[3] = {0, 0, 0};      ///< u in that cell's reference coordinates.
};

/// Exact closest point of x = A u + b over the region's parameter box: the
/// unconstrained least-squares solution when it lies in the box, otherwise
/// the best of the solutions restricted to each face of the box (the problem
/// is convex, so its minimizer is the unconstrained minimizer of the face
/// whose relative interior holds it). At most 3^paramDim tiny solves.
RegionSolution SolveAffineRegion(const AffineRegion& region, const double* point);

/// The affine regions of every B-spline patch of `nets` (whose cells have
/// the solvers `solvers`, built): for each patch's grid of spans, greedy
/// maximal boxes of at least 2 affine cells whose maps agree at every cell
/// corner to kAffineRegionTolerance times the patch's size (plus the
/// rounding of large coordinates, kernels/tolerances.h), and whose map is
/// well conditioned. In patch order.
std::vector<AffineRegion> FindAffineRegions(const BezierNets& nets, const std::vector<kernels::CellSolver>& solvers);

}  // namespace invmap::engine
