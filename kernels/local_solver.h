// Algorithm 5: the active-set Newton solve for a closest point on one cell,
// local: it converges to a constrained local minimum (a KKT point) of the
// squared distance near its starting point.
#pragma once

#include <limits>

#include "kernels/cell_map.h"

namespace invmap::kernels {

/// Result of one local solve.
struct LocalSolveResult {
  double ref[3] = {0, 0, 0};      ///< Reference coordinates of the KKT point.
  double closest[3] = {0, 0, 0};  ///< The map at ref.
  double squaredDistance = 0.0;
  bool onBoundary = false;  ///< Some constraint is enforced at the solution.
  bool converged = false;   ///< Stopped on the residual or step tolerance (not on the iteration cap).
  /// Converged and IsKktPoint (kernels/kkt_point.h) holds at ref (only
  /// computed with LocalSolveOptions::checkKkt).
  bool kkt = false;
  /// Stopped at ref on LocalSolveOptions::exclusionLevel (not converged).
  bool aboveLevel = false;
  int iterations = 0;
};

/// The local model of the squared distance at a solve's answer: what a
/// nearby point's solve needs to predict its own start (engine/warm_start.h).
struct AnswerModel {
  bool known = false;  ///< The fields below hold the answer's model (unset otherwise).
  double jacobian[3][3];  ///< dx_k/du_i at the answer.
  /// The Hessian of half the squared distance to the query point, J^T J +
  /// sum_k r_k d2x_k, at the answer or within a final Newton step of it
  /// (zero when the solve evaluated no second derivatives there).
  double hessian[3][3];
};

/// Options of the local solve, relative to the cell's size (see tolerances.h).
struct LocalSolveOptions {
  bool affine = false;  ///< The map is affine: no second derivatives, one exact step per active set.
  double size = 1.0;    ///< Length scale: the diagonal of the control-point box.
  int maxIterations = 100;
  /// Give up (converged = false) when an iterate on the boundary is still
  /// farther than kBoundaryGiveUp * size (kernels/tolerances.h) from the point: an inside test
  /// (7.3.2.1) only wants the point itself, and a point outside the cell
  /// drives the full-rank step onto the boundary at once.
  bool stopAtBoundary = false;
  /// Fill LocalSolveResult::kkt, from the map's derivatives at the solution
  /// (the solve evaluates them there, instead of the value alone).
  bool checkKkt = false;
  /// Stop (LocalSolveResult::aboveLevel) at the first iterate whose
  /// TangentPlaneLowerBound at this squared distance is positive, once
  /// confirmExclusion agrees: for a caller that only wants points below the
  /// level. -infinity: never.
  double exclusionLevel = -std::numeric_limits<double>::infinity();
  /// Called (with exclusionContext) at most once, at the first positive
  /// plane: true when the plane bounds the squared distance over the whole
  /// cell (the convexity it needs); false lets the solve go on to convergence.
  bool (*confirmExclusion)(const void* context) = nullptr;
  const void* exclusionContext = nullptr;
  /// When set, receives the model at the answer (with checkKkt, whose final
  /// evaluation gives the Jacobian; known = false otherwise).
  AnswerModel* model = nullptr;
};

/// Minimizes |x(u) - point|^2 over the reference domain starting at
/// `startRef` (clamped into the domain). Newton in the orthogonal basis of
/// the free face; constraints enforced by step scaling and released by their
/// Lagrange multipliers; Levenberg-Marquardt and then gradient-descent
/// fallbacks when the Newton direction is not a descent direction; Armijo
/// backtracking so every step decreases the distance. Volume cells with no
/// enforced constraint use the full-rank step -J^-1 r (7.3.2.1). Never
/// produces NaN for finite input, whatever the cell's degeneracy.
LocalSolveResult LocalSolve(const CellView& cell, const double* point, const double* startRef,
                            const LocalSolveOptions& options);

}  // namespace invmap::kernels
