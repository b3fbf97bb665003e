// The local solve of a pair of cells: a constrained Newton method over the
// joint parameters w = (u, v) that converges to a local minimum (a KKT
// point) of |x(u) - y(v)|^2 near its start. The pair search
// (kernels/pair_search.h) makes it global.
#pragma once

#include "kernels/pair_problem.h"
#include "kernels/tolerances.h"

namespace invmap::kernels {

/// What the KKT check found at a point: the constraints it holds (their
/// slack is rounding) and their multipliers, of f = |z|^2 / 2: grad f =
/// sum over active c of multiplier_c normal_c plus a residual the check
/// judged negligible.
struct PairKkt {
  bool kkt = false;
  int numActive = 0;
  int active[kMaxPairConstraints] = {};
  double multiplier[kMaxPairConstraints] = {};
  double gradient[kMaxPairParams] = {};  ///< grad f at the point (joint parameters).
};

/// Result of one local solve.
struct PairLocalResult {
  double w[kMaxPairParams] = {};  ///< Joint parameters of the answer.
  double x[3] = {0, 0, 0};        ///< Side A's point (common frame).
  double y[3] = {0, 0, 0};        ///< Side B's point.
  double squaredDistance = 0.0;
  bool converged = false;   ///< Stopped on a negligible step or decrease (not the iteration cap).
  bool onBoundary = false;  ///< Some constraint holds at w.
  int iterations = 0;
  PairKkt kkt;              ///< The KKT check at w (kkt.kkt false unless converged).
};

struct PairLocalOptions {
  int maxIterations = 100;
  /// Length scale of the tolerances: the cells' sizes, summed.
  double size = 1.0;
  /// The longest unchecked final Newton step (tolerances.h's kFinalStep), in
  /// the solve's own parameters. A solve on subdomains of the cells, whose
  /// parameters stretch the cells' by 1 / width, takes kFinalStep / width:
  /// the same step in the cells' parameters, else it stops short of the
  /// minimum by more than the cells' KKT test accepts.
  double finalStep = kFinalStep;
};

/// Minimizes |x(u) - y(v)|^2 over the pair's domain from `start` (projected
/// into the domain first). Each step solves the quadratic model (the exact
/// Hessian where it is positive definite, else Gauss-Newton with a
/// Levenberg-Marquardt shift) under the domain's linear constraints by a
/// primal active-set method, then backtracks (Armijo) along it: every step
/// stays in the domain and decreases the distance. Never produces NaN for
/// finite input.
PairLocalResult PairLocalSolve(const PairSide& a, const PairSide& b, const PairLayout& layout, const double* start,
                               const PairLocalOptions& options);

/// The first-order (KKT) conditions of |z|^2 at w from the jet there (order
/// Second): the gradient, less the constraints' multipliers, is
/// negligible along every direction of the free face (each judged by how far
/// z moves along it, as the point solves judge theirs), and no active
/// constraint's multiplier asks to release it. A point where z vanishes (to
/// `size` times the distance tolerance) is a global minimum and passes.
PairKkt CheckPairKkt(const PairLayout& layout, const PairJet& jet, const double* w, int ambientDim, double size);

}  // namespace invmap::kernels
