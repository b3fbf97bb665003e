#include "kernels/local_solver.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/active_set.h"
#include "kernels/cramer.h"
#include "kernels/tangent_plane.h"
#include "kernels/tolerances.h"

namespace invmap::kernels {
namespace {

// Every vector and matrix is 3 x 3 (or 3) and zero-padded past the cell's
// dimensions: fixed sizes keep the solve off the heap and vectorized.
using Matrix = Eigen::Matrix3d;
using Vector = Eigen::Vector3d;

/// Pads the unused diagonal of a reduced matrix with ones, so a face of
/// dimension m < 3 factors like its m x m block.
void PadDiagonal(int m, Matrix* a) {
  for (int c = m; c < 3; ++c) (*a)(c, c) = 1.0;
}

/// |x - point|^2 for the mapped point x of `jet` (ambientDim coordinates).
double SquaredDistance(const MapJet& jet, const double* point, int ambientDim) {
  double f = 0.0;
  for (int k = 0; k < ambientDim; ++k) f += (jet.x[k] - point[k]) * (jet.x[k] - point[k]);
  return f;
}

/// The rounding level of f = |r|^2 (r = x - point): the map's coordinates
/// carry errors of a few ulps of the coordinates' magnitude, and f doubles
/// their relative size.
double RoundingOfF(const double* point, const double* r, int ambientDim, double size, double f) {
  double magnitude = size;
  for (int k = 0; k < ambientDim; ++k) magnitude = std::max(magnitude, std::abs(point[k]) + std::abs(r[k]));
  const double rError = kMapRounding * magnitude;
  return 2.0 * std::sqrt(f) * rError + rError * rError;
}

/// |v| of 3 coordinates; where the sum of squares overflows or underflows
/// (cells near the ends of the double range), summed in units of the
/// largest coordinate instead.
double Norm(const double* v) {
  const double length2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  if (length2 > 1e-300 && length2 < 1e300) return std::sqrt(length2);
  const double largest = std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])});
  if (!(largest > 0.0) || !std::isfinite(largest)) return largest;
  const double a = v[0] / largest, b = v[1] / largest, c = v[2] / largest;
  return largest * std::sqrt(a * a + b * b + c * c);
}

/// The scale of the stationarity, release and KKT tests: a slope r . J v
/// along a direction v of the parameters is judged against perLength times
/// how far the map moves along v, |J v| (never less than kThinDirection
/// times the cell's size). Each direction by its own scale: a direction the
/// map stretches little (the thickness of a thin cell, the width of a narrow
/// ribbon) or much (next to a heavy weight) would otherwise be judged by the
/// cell's size, and a slope along a thickness of 1e-6 of it passed for
/// stationary with the point 1e-8 of the size away (QA's thin hexes).
struct DirectionScale {
  const MapJet& jet;
  int ambientDim, paramDim;
  double perLength;    ///< Tolerance per unit of mapped length.
  double floorLength;  ///< kThinDirection times the cell's size.

  /// |J v|: how far the map moves per unit of the parameter step v.
  double MappedLength(const double* v) const {
    double moved[3] = {0, 0, 0};
    for (int k = 0; k < ambientDim; ++k) {
      for (int i = 0; i < paramDim; ++i) moved[k] += jet.d1[k][i] * v[i];
    }
    return Norm(moved);
  }
  /// |J e_i|: how far the map moves per unit of parameter i.
  double ColumnLength(int i) const {
    const double column[3] = {jet.d1[0][i], jet.d1[1][i], ambientDim > 2 ? jet.d1[2][i] : 0.0};
    return Norm(column);
  }
  /// The tolerance of a slope along a direction the map moves `mappedLength`
  /// per unit. (A product, not squares: those overflow long before either
  /// factor; +infinity where even it does.)
  double Tolerance(double mappedLength) const { return perLength * std::max(mappedLength, floorLength); }
};

/// True when the gradient `grad` vanishes on the free face of `face` up to
/// the tolerances of `scale`: along directions of the face whose images
/// under J are orthogonal (the longest first, the others with its part
/// removed), each judged by its own mapped length. The face basis's own
/// columns mix parameters: next to a heavy weight one column of J can be
/// 1e12 times another, and a column holding a share of it would lend the
/// test that scale along directions the map hardly stretches (in a thin
/// cell, the thickness would take the length's scale).
bool IsStationaryOnFace(const FaceBasis& face, const double* grad, const DirectionScale& scale) {
  const int m = face.columns;
  double along[3][3] = {};  // along[c]: direction c of the face, reduced coordinates
  double image[3][3] = {};  // J T along[c], in units of `unit`
  double largest = 0.0;
  for (int c = 0; c < m; ++c) {
    along[c][c] = 1.0;
    for (int k = 0; k < scale.ambientDim; ++k) {
      for (int i = 0; i < scale.paramDim; ++i) image[c][k] += scale.jet.d1[k][i] * face.t[i][c];
      largest = std::max(largest, std::abs(image[c][k]));
    }
  }
  // Near the ends of the double range, the images in units of a power of
  // two near the largest (exact), so that their squares neither overflow
  // nor underflow.
  double unit = 1.0;
  if ((largest > 1e150 || largest < 1e-150) && largest > 0.0 && std::isfinite(largest)) {
    unit = std::ldexp(1.0, std::ilogb(largest));
    for (int c = 0; c < m; ++c) {
      for (double& x : image[c]) x /= unit;
    }
  }
  const auto length2 = [&](const double* v) { return v[0] * v[0] + v[1] * v[1] + v[2] * v[2]; };
  bool placed[3] = {false, false, false};
  for (int step = 0; step < m; ++step) {
    int longest = -1;
    for (int c = 0; c < m; ++c) {
      if (!placed[c] && (longest < 0 || length2(image[c]) > length2(image[longest]))) longest = c;
    }
    placed[longest] = true;
    const double norm2 = length2(image[longest]);
    if (!(norm2 > 0.0)) break;  // the rest does not move the map at all
    for (int c = 0; c < m; ++c) {
      if (placed[c]) continue;
      double share = 0.0;
      for (int k = 0; k < 3; ++k) share += image[longest][k] * image[c][k];
      share /= norm2;
      for (int k = 0; k < 3; ++k) {
        image[c][k] -= share * image[longest][k];
        along[c][k] -= share * along[longest][k];
      }
    }
  }
  for (int c = 0; c < m; ++c) {
    const double norm = std::sqrt(length2(along[c]));
    double slope = 0.0;
    for (int i = 0; i < scale.paramDim; ++i) {
      double direction = 0.0;
      for (int j = 0; j < m; ++j) direction += face.t[i][j] * along[c][j];
      slope += direction * grad[i];
    }
    if (std::abs(slope) / norm > scale.Tolerance(unit * std::sqrt(length2(image[c])) / norm)) return false;
  }
  return true;
}

/// Largest step fraction in (0, 1] that keeps every free barycentric
/// coordinate non-negative, and the constraint that blocks it (factor, index).
double FeasibleFraction(const CellShape& shape, const ActiveSet& active, const double* ref, const double* step,
                        int* blockFactor, int* blockIndex) {
  double alpha = 1.0;
  *blockFactor = -1;
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& fac = shape.factor(f);
    double lambda[4], dLambda[4];
    FactorBarycentric(shape, f, ref, lambda);
    dLambda[0] = 0.0;
    for (int i = 0; i < fac.dim; ++i) {
      dLambda[i + 1] = step[fac.offset + i];
      dLambda[0] -= step[fac.offset + i];
    }
    for (int k = 0; k <= fac.dim; ++k) {
      if ((active.enforced[f] & (1u << k)) || dLambda[k] >= 0.0) continue;
      // Most constraints are nowhere near blocking: those with twice the
      // room the step needs skip the division (the test is exact: their
      // fraction is at least 2 alpha, rounding included).
      const double room = std::max(0.0, lambda[k]);
      if (room >= 2.0 * alpha * -dLambda[k]) continue;
      const double a = room / -dLambda[k];
      if (a < alpha) {
        alpha = a;
        *blockFactor = f;
        *blockIndex = k;
      }
    }
  }
  return alpha;
}

/// Puts `ref` exactly on the face of every enforced constraint (rounding in
/// the steps would otherwise leave it a hair off).
void SnapToFace(const CellShape& shape, const ActiveSet& active, double* ref) {
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& fac = shape.factor(f);
    double* s = ref + fac.offset;
    for (int k = 1; k <= fac.dim; ++k) {
      if (active.enforced[f] & (1u << k)) s[k - 1] = 0.0;
    }
    if (active.enforced[f] & 1u) {
      // lambda_0 = 0: the free coordinates sum to one. Put the excess on the
      // largest free coordinate.
      double sum = 0.0;
      int largest = -1;
      for (int i = 0; i < fac.dim; ++i) {
        sum += s[i];
        if (!(active.enforced[f] & (1u << (i + 1))) && (largest < 0 || s[i] > s[largest])) largest = i;
      }
      if (largest >= 0) s[largest] += 1.0 - sum;
    }
    for (int i = 0; i < fac.dim; ++i) s[i] = std::clamp(s[i], 0.0, 1.0);
  }
}

/// True when `step` decreases barycentric coordinate k of factor f.
bool MovesOut(const CellShape& shape, int f, int k, const double* step) {
  const SimplexFactor& fac = shape.factor(f);
  double d = 0.0;
  if (k > 0) {
    d = step[fac.offset + k - 1];
  } else {
    for (int i = 0; i < fac.dim; ++i) d -= step[fac.offset + i];
  }
  return d < 0.0;
}

/// The enforced constraints of a point: barycentric coordinates at zero.
ActiveSet ActiveSetAt(const CellShape& shape, const double* ref) {
  ActiveSet active;
  for (int f = 0; f < shape.numFactors(); ++f) {
    double lambda[4];
    FactorBarycentric(shape, f, ref, lambda);
    const int dim = shape.factor(f).dim;
    for (int k = 0; k <= dim; ++k) {
      if (lambda[k] <= kOnFaceTolerance) active.enforced[f] |= 1u << k;
    }
    // Keep one coordinate free (a vertex leaves exactly one).
    if (active.enforced[f] == (1u << (dim + 1)) - 1) active.enforced[f] &= ~1u;
  }
  return active;
}

/// x = -H^-1 g for the leading m x m block of the symmetric H, by an LDL^T
/// factorization (x[m..2] = 0). False unless that block is positive
/// definite and x is finite and descends (x . g < 0).
bool NewtonStepOf(const double h[3][3], int m, const double* g, double* x) {
  // LDL^T: l[i][j] (j < i) below the diagonal, d[i] on it.
  double l[3][3] = {}, d[3];
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < i; ++j) {
      double v = h[i][j];
      for (int k = 0; k < j; ++k) v -= l[i][k] * d[k] * l[j][k];
      l[i][j] = v / d[j];
    }
    double v = h[i][i];
    for (int k = 0; k < i; ++k) v -= l[i][k] * d[k] * l[i][k];
    if (!(v > 0.0)) return false;
    d[i] = v;
  }
  double y[3];
  for (int i = 0; i < m; ++i) {
    y[i] = -g[i];
    for (int k = 0; k < i; ++k) y[i] -= l[i][k] * y[k];
  }
  double slope = 0.0;
  for (int i = m - 1; i >= 0; --i) {
    x[i] = y[i] / d[i];
    for (int k = i + 1; k < m; ++k) x[i] -= l[k][i] * x[k];
    slope += x[i] * g[i];
  }
  for (int i = m; i < 3; ++i) x[i] = 0.0;
  return std::isfinite(slope) && slope < 0.0;
}

/// Newton step -H^-1 g of f / 2 with H = J^T J + sum_k r_k d2x_k, over the
/// m parameters coords[0 .. m) (the others keep step 0). False unless that
/// block of H is positive definite and the step is finite and descends.
bool NewtonStepOver(const MapJet& jet, const double* r, const double* grad, const int* coords, int m, int ad,
                    double* step) {
  double h[3][3], g[3] = {0, 0, 0}, x[3];  // g zeroed for the compiler: it is read only below m
  for (int a = 0; a < m; ++a) {
    const int i = coords[a];
    g[a] = grad[i];
    for (int b = 0; b <= a; ++b) {
      const int j = coords[b];
      double v = 0.0;
      for (int k = 0; k < ad; ++k) v += jet.d1[k][i] * jet.d1[k][j] + r[k] * jet.d2[k][i][j];
      h[a][b] = h[b][a] = v;
    }
  }
  if (!NewtonStepOf(h, m, g, x)) return false;
  step[0] = step[1] = step[2] = 0.0;
  for (int a = 0; a < m; ++a) step[coords[a]] = x[a];
  return true;
}

/// Cells of line factors (lines, quads, hexes): the parameters whose factor
/// has no enforced constraint. Other cells: -1.
int FreeLineParameters(const CellShape& shape, const ActiveSet& active, int* coords) {
  int m = 0;
  for (int f = 0; f < shape.numFactors(); ++f) {
    if (shape.factor(f).dim != 1) return -1;
    if (active.enforced[f] == 0) coords[m++] = shape.factor(f).offset;
  }
  return m;
}

/// True when every parameter of `coords` (count of them) has a slope within
/// its own tolerance: a cell of line factors, whose face directions are its
/// free parameters, judged as IsKktPoint judges it.
bool FreeParametersStationary(const int* coords, int count, const double* grad, const DirectionScale& scale) {
  for (int a = 0; a < count; ++a) {
    if (!(std::abs(grad[coords[a]]) <= scale.Tolerance(scale.ColumnLength(coords[a])))) return false;
  }
  return true;
}

/// The step -J^-1 r of a volume cell (pd = ambient dimension 2 or 3) by
/// Cramer's rule; false when J is singular to kSingularTolerance (as the
/// general path decides) or the step is not finite.
bool FullRankStep(const MapJet& jet, const double* r, int pd, double size, double* step) {
  step[2] = 0.0;
  if (pd == 2) {
    const double det = jet.d1[0][0] * jet.d1[1][1] - jet.d1[0][1] * jet.d1[1][0];
    if (!(std::abs(det) > kSingularTolerance * size * size)) return false;
    step[0] = -(r[0] * jet.d1[1][1] - r[1] * jet.d1[0][1]) / det;
    step[1] = -(jet.d1[0][0] * r[1] - jet.d1[1][0] * r[0]) / det;
    return std::isfinite(step[0]) && std::isfinite(step[1]);
  }
  // Columns of J: the derivatives along each parameter.
  double c[3][3];
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) c[i][k] = jet.d1[k][i];
  }
  const double det = Determinant3(c[0], c[1], c[2]);
  if (!(std::abs(det) > kSingularTolerance * size * size * size)) return false;
  const double minusR[3] = {-r[0], -r[1], -r[2]};
  CramerSolve3(c[0], c[1], c[2], det, minusR, step);
  return std::isfinite(step[0]) && std::isfinite(step[1]) && std::isfinite(step[2]);
}

/// The step lengths below which a move is negligible (kStepTolerance) and
/// an unchecked Newton step is final (kFinalStep), at an iterate whose map
/// has the jet `jet`. Both are meant for a map that moves about `size` per
/// unit of reference coordinate; where it moves faster (|J| above size: a
/// rational cell with weights many orders of magnitude apart crosses a
/// whole control leg in 1e-15 of its parameter) they shrink in proportion,
/// so that the mapped point still moves less than they allow.
struct StepLimits {
  double negligible = kStepTolerance;
  double final = kFinalStep;
};
StepLimits StepLimitsAt(const MapJet& jet, int pd, int ad, double size) {
  double jac2 = 0.0;
  for (int k = 0; k < ad; ++k) {
    for (int i = 0; i < pd; ++i) jac2 += jet.d1[k][i] * jet.d1[k][i];
  }
  StepLimits limits;
  if (jac2 > size * size) {
    const double shrink = size / std::sqrt(jac2);
    limits.negligible *= shrink;
    limits.final *= shrink;
  }
  return limits;
}

enum class StepOutcome { Moved, Blocked, Negligible, Rejected, Final };

/// Armijo backtracking along the feasible part of `step`. On success moves
/// `ref` (and enforces the blocking constraint when the whole feasible step
/// was taken); Negligible when the accepted move is below limits.negligible or
/// the decrease it promises is below `fNoise`, the rounding level of f (no
/// evaluation could then tell a decrease from rounding). A short Newton step
/// (`newton`, within the domain, at most limits.final) that promises only such
/// a decrease is in the quadratic convergence region: it is taken unchecked,
/// and the outcome is Final. (A long step promising so little means a nearly
/// singular Hessian, where the model cannot be trusted.)
/// Trial points are evaluated to `trialOrder` into *trialJet, so after Moved
/// it holds the map at the new `ref` for the next iteration.
StepOutcome LineSearch(const CellView& cell, const double* point, ActiveSet& active, double f, double fNoise,
                       const StepLimits& limits, const Vector& g, const Vector& step, bool newton,
                       JetOrder trialOrder, MapJet* trialJet, double* ref) {
  const CellShape& shape = cell.shape;
  const int pd = shape.paramDim();
  int blockFactor = -1, blockIndex = -1;
  const double feasible = FeasibleFraction(shape, active, ref, step.data(), &blockFactor, &blockIndex);
  const double slope = 2.0 * g.dot(step);  // derivative of |r|^2 along the step
  if (!(slope < 0.0)) return StepOutcome::Rejected;
  const double length = step.norm();
  if (blockFactor >= 0 && feasible * length <= limits.negligible) {
    // Already on that constraint's face (up to rounding): a descent step
    // that leaves the domain at once means the constraint becomes active.
    active.enforced[blockFactor] |= 1u << blockIndex;
    return StepOutcome::Blocked;
  }
  if (newton && blockFactor < 0 && -slope <= fNoise && length <= limits.final) {
    for (int i = 0; i < pd; ++i) ref[i] += step[i];
    return StepOutcome::Final;
  }
  double alpha = feasible;
  double trial[3];
  for (int halving = 0; halving < 60; ++halving) {
    if (alpha * length <= limits.negligible || -alpha * slope <= fNoise) return StepOutcome::Negligible;
    for (int i = 0; i < pd; ++i) trial[i] = ref[i] + alpha * step[i];
    EvaluateMap(cell, trial, trialOrder, trialJet);
    const double fTrial = SquaredDistance(*trialJet, point, cell.ambientDim);
    if (fTrial <= f + kSufficientDecrease * alpha * slope && fTrial < f) {
      std::copy(trial, trial + pd, ref);
      if (blockFactor >= 0 && alpha == feasible) {
        active.enforced[blockFactor] |= 1u << blockIndex;
        return StepOutcome::Blocked;
      }
      return StepOutcome::Moved;
    }
    alpha *= 0.5;
  }
  return StepOutcome::Rejected;
}

/// The map at the iterate (to `order`, when `valid`) and a buffer for the
/// line search's trial points: an accepted trial's evaluation serves the next
/// iteration, so a step costs one evaluation of the map, not two.
struct JetCache {
  JetCache() = default;
  JetCache(const JetCache&) = delete;
  JetCache& operator=(const JetCache&) = delete;

  /// Makes *atRef the map at `ref` to at least `need`.
  void EnsureAt(const CellView& cell, const double* ref, JetOrder need) {
    if (valid && order >= need) return;
    EvaluateMap(cell, ref, need, atRef);
    for (int i = 0; i < 3; ++i) at[i] = ref[i];
    valid = true;
    order = need;
  }
  /// The trial point `ref`, evaluated to `trialOrder`, became the iterate.
  void AcceptTrial(JetOrder trialOrder, const double* ref) {
    std::swap(atRef, trial);
    for (int i = 0; i < 3; ++i) at[i] = ref[i];
    valid = true;
    order = trialOrder;
  }

  MapJet jets[2];
  MapJet* atRef = &jets[0];
  MapJet* trial = &jets[1];
  /// Where *atRef was evaluated (it stays there when `valid` turns false).
  /// Copied by loops: std::copy of its 3 values compiled to a memmove call.
  double at[3] = {0, 0, 0};
  bool valid = false;
  JetOrder order = JetOrder::Value;
};

/// The Hessian of half the squared distance from `point`, J^T J + sum_k r_k
/// d2x_k with r = x - point, from a second-order jet.
void DistanceHessian(const MapJet& jet, const double* point, int pd, int ad, double (*hessian)[3]) {
  for (int i = 0; i < pd; ++i) {
    for (int j = 0; j < pd; ++j) {
      double h = 0.0;
      for (int k = 0; k < ad; ++k) h += jet.d1[k][i] * jet.d1[k][j] + (jet.x[k] - point[k]) * jet.d2[k][i][j];
      hessian[i][j] = h;
    }
  }
}

/// Releases the enforced constraints of a start on the boundary that the
/// descent direction there points away from (negative multiplier):
/// otherwise the solve would first converge along their face, and only then
/// release them. `jet`: the map at the start, to first order at least.
void ReleaseInwardConstraints(const CellView& cell, const MapJet& jet, const double* point, ActiveSet* active) {
  const CellShape& shape = cell.shape;
  double grad[3] = {0, 0, 0};
  for (int i = 0; i < shape.paramDim(); ++i) {
    for (int k = 0; k < cell.ambientDim; ++k) grad[i] += jet.d1[k][i] * (jet.x[k] - point[k]);
  }
  const ActiveSet start = *active;
  for (int f = 0; f < shape.numFactors(); ++f) {
    for (int k = 0; k <= shape.factor(f).dim; ++k) {
      if ((start.enforced[f] & (1u << k)) && ReleaseDerivative(shape, start, f, k, grad) < 0.0) {
        active->enforced[f] &= ~(1u << k);
      }
    }
  }
}

/// How LineFactorNewton left the solve.
enum class FastOutcome { Converged, AboveLevel, Handover };

/// The iterations of a curve or surface cell of line factors (lines and
/// quads in a higher-dimensional space) in their common case: Newton steps
/// of the full Hessian over the free parameters (those of no enforced
/// constraint: on a face, the others stay at 0 or 1) that stay in the domain
/// and pass the Armijo test at once, until the face is stationary and no
/// enforced constraint's multiplier asks for a release. The steps, tests and
/// tolerances are the general loop's (see LocalSolve); what is left out is
/// its active-set machinery, and the dimensions are fixed at compile time.
/// That machinery's generic loops took about twice the time of the map's
/// evaluation on a near point of a bicubic surface (measured). Any other
/// case (a step that leaves the domain or fails the Armijo test, a Hessian
/// that is not positive definite, a constraint to release) hands over to the
/// general loop at the current iterate, with the active set unchanged.
template <int PD, int AD>
FastOutcome LineFactorNewton(const CellView& cell, const double* point, const LocalSolveOptions& options,
                             const ActiveSet& active, double* ref, JetCache* jets, bool* exclusionPending, int* iter,
                             LocalSolveResult* result) {
  const double size = options.size;
  // Parameter i is factor i's: free, or held at 0 (constraint 1 enforced,
  // released toward +u_i) or at 1 (constraint 0, released toward -u_i).
  int freeCoords[3], m = 0;
  double releaseSign[3] = {0, 0, 0};
  for (int i = 0; i < PD; ++i) {
    if (active.enforced[i] == 0) {
      freeCoords[m++] = i;
    } else {
      releaseSign[i] = (active.enforced[i] & 2u) ? 1.0 : -1.0;
    }
  }
  // True when no enforced constraint's multiplier is below minus its tolerance.
  const auto noRelease = [&](const double* grad, const double* tolerance) {
    for (int i = 0; i < PD; ++i) {
      if (releaseSign[i] != 0.0 && releaseSign[i] * grad[i] < -tolerance[i]) return false;
    }
    return true;
  };
  for (; *iter < options.maxIterations; ++*iter) {
    result->iterations = *iter + 1;
    jets->EnsureAt(cell, ref, JetOrder::Second);
    const MapJet& jet = *jets->atRef;
    double r[AD], f = 0.0;
    for (int k = 0; k < AD; ++k) {
      r[k] = jet.x[k] - point[k];
      f += r[k] * r[k];
    }
    if (*exclusionPending &&
        TangentPlaneLowerBound(cell.shape, AD, jet, point, ref, options.exclusionLevel, size) > 0.0) {
      *exclusionPending = false;
      if (options.confirmExclusion(options.exclusionContext)) return FastOutcome::AboveLevel;
    }
    double grad[3] = {0, 0, 0};
    for (int i = 0; i < PD; ++i) {
      for (int k = 0; k < AD; ++k) grad[i] += jet.d1[k][i] * r[k];
    }
    // Each parameter's slope against its own tolerance (DirectionScale).
    const DirectionScale scale{jet, AD, PD, kGradientTolerance * (size + std::sqrt(f)), kThinDirection * size};
    double tolerance[3];
    bool stationary = true;
    for (int i = 0; i < PD; ++i) tolerance[i] = scale.Tolerance(scale.ColumnLength(i));
    for (int a = 0; a < m; ++a) stationary = stationary && std::abs(grad[freeCoords[a]]) <= tolerance[freeCoords[a]];
    if (stationary) return noRelease(grad, tolerance) ? FastOutcome::Converged : FastOutcome::Handover;
    const double fNoise = RoundingOfF(point, r, AD, size, f);

    double step[3];
    if (!NewtonStepOver(jet, r, grad, freeCoords, m, AD, step)) return FastOutcome::Handover;
    double trial[3] = {ref[0], ref[1], ref[2]}, slope = 0.0, length2 = 0.0;
    bool inside = true;
    for (int a = 0; a < m; ++a) {
      const int i = freeCoords[a];
      trial[i] = ref[i] + step[i];
      inside = inside && trial[i] >= 0.0 && trial[i] <= 1.0;
      slope += 2.0 * grad[i] * step[i];
      length2 += step[i] * step[i];
    }
    const double length = std::sqrt(length2);
    if (!inside) return FastOutcome::Handover;
    const StepLimits limits = StepLimitsAt(jet, PD, AD, size);
    if (-slope <= fNoise && length <= limits.final) {
      // In the quadratic region: the step is taken unchecked, and on a face
      // the multipliers of this iterate decide (as in the general loop).
      std::copy(trial, trial + PD, ref);
      jets->valid = false;
      return noRelease(grad, tolerance) ? FastOutcome::Converged : FastOutcome::Handover;
    }
    if (length <= limits.negligible || -slope <= fNoise) return FastOutcome::Handover;
    EvaluateMap(cell, trial, JetOrder::Second, jets->trial);
    const double fTrial = SquaredDistance(*jets->trial, point, AD);
    if (!(fTrial <= f + kSufficientDecrease * slope && fTrial < f)) return FastOutcome::Handover;
    std::copy(trial, trial + PD, ref);
    jets->AcceptTrial(JetOrder::Second, ref);
  }
  return FastOutcome::Handover;
}

/// LineFactorNewton for the cell's dimensions; Handover at once for cells it
/// does not cover (a volume, a simplex factor, an affine map).
FastOutcome LineFactorNewtonFor(const CellView& cell, const double* point, const LocalSolveOptions& options,
                                const ActiveSet& active, double* ref, JetCache* jets, bool* exclusionPending,
                                int* iter, LocalSolveResult* result) {
  const CellShape& shape = cell.shape;
  if (options.affine || !shape.isBox()) return FastOutcome::Handover;
  const int pd = shape.paramDim();
  if (pd == 2 && cell.ambientDim == 3) {
    return LineFactorNewton<2, 3>(cell, point, options, active, ref, jets, exclusionPending, iter, result);
  }
  if (pd == 1 && cell.ambientDim == 2) {
    return LineFactorNewton<1, 2>(cell, point, options, active, ref, jets, exclusionPending, iter, result);
  }
  if (pd == 1 && cell.ambientDim == 3) {
    return LineFactorNewton<1, 3>(cell, point, options, active, ref, jets, exclusionPending, iter, result);
  }
  return FastOutcome::Handover;
}

}  // namespace

LocalSolveResult LocalSolve(const CellView& cell, const double* point, const double* startRef,
                            const LocalSolveOptions& options) {
  const CellShape& shape = cell.shape;
  const int pd = shape.paramDim();
  const int ad = cell.ambientDim;
  const bool fullRank = pd == ad;
  const double size = options.size;
  const JetOrder order = options.affine ? JetOrder::First : JetOrder::Second;

  LocalSolveResult result;
  double ref[3] = {0, 0, 0};
  std::copy(startRef, startRef + pd, ref);
  ClampToDomain(shape, ref);
  ActiveSet active = ActiveSetAt(shape, ref);
  SnapToFace(shape, active, ref);

  int releases = 0;
  bool fullRankAllowed = true;
  int releasedFactor = -1, releasedIndex = -1;  // the constraint released last
  JetCache jets;
  bool exclusionPending = options.confirmExclusion && options.exclusionLevel > -std::numeric_limits<double>::infinity();
  // A start on the boundary (a neighbour's edge, a control point there)
  // keeps only the constraints the descent direction presses against.
  // (Volumes keep theirs: their starts are inset, see NearestControlPointStart.)
  if (!fullRank && (active.enforced[0] != 0 || active.enforced[1] != 0 || active.enforced[2] != 0)) {
    jets.EnsureAt(cell, ref, order);
    ReleaseInwardConstraints(cell, *jets.atRef, point, &active);
  }
  int iter = 0;
  const FastOutcome fast =
      LineFactorNewtonFor(cell, point, options, active, ref, &jets, &exclusionPending, &iter, &result);
  result.converged = fast == FastOutcome::Converged;
  result.aboveLevel = fast == FastOutcome::AboveLevel;
  for (; fast == FastOutcome::Handover && iter < options.maxIterations; ++iter) {
    result.iterations = iter + 1;
    // 7.3.2.1 only while no constraint has been met: a point that drove the
    // solve onto the boundary is outside the cell, where -J^-1 r keeps
    // pointing back out (and near a collapsed edge, cycles with releases).
    const bool noneEnforced = active.enforced[0] == 0 && active.enforced[1] == 0 && active.enforced[2] == 0;
    fullRankAllowed = fullRankAllowed && noneEnforced;
    const bool useFullRank = fullRank && fullRankAllowed;
    const JetOrder need = useFullRank ? JetOrder::First : order;
    jets.EnsureAt(cell, ref, need);
    const MapJet& jet = *jets.atRef;
    double r[3] = {0, 0, 0};
    double f = 0.0;
    for (int k = 0; k < ad; ++k) {
      r[k] = jet.x[k] - point[k];
      f += r[k] * r[k];
    }
    if (exclusionPending && TangentPlaneLowerBound(shape, ad, jet, point, ref, options.exclusionLevel, size) > 0.0) {
      exclusionPending = false;
      if (options.confirmExclusion(options.exclusionContext)) {
        result.aboveLevel = true;
        break;
      }
    }
    // On the boundary and still far from the point: it most likely lies
    // outside the cell. (Giving up on a point inside only costs the caller a
    // full solve.)
    if (options.stopAtBoundary && !noneEnforced && f > kBoundaryGiveUp * kBoundaryGiveUp * size * size) break;
    double grad[3] = {0, 0, 0};  // gradient of f / 2 = J^T r
    for (int i = 0; i < pd; ++i) {
      for (int k = 0; k < ad; ++k) grad[i] += jet.d1[k][i] * r[k];
    }
    const DirectionScale scale{jet, ad, pd, kGradientTolerance * (size + std::sqrt(f)), kThinDirection * size};
    const double fNoise = RoundingOfF(point, r, ad, size, f);
    const StepLimits limits = StepLimitsAt(jet, pd, ad, size);

    const Vector g = Eigen::Map<const Vector>(grad);
    // The common cases without the fallbacks' set-up: in the interior, the
    // step -J^-1 r of a volume cell (7.3.2.1) or the Newton step of the full
    // Hessian; on a face of a cell of line factors, the Newton step over the
    // free parameters. Both are the reduced step below (whose basis is then
    // square, or picks the free parameters). Anything else falls through.
    int freeCoords[3] = {0, 1, 2};
    int freeCount = 0;
    bool freeStationary = true;
    // A cell of line factors is judged along its free parameters (-1: not one).
    int lineCoords[3];
    const int lineCount = FreeLineParameters(shape, active, lineCoords);
    if (releasedFactor < 0 && noneEnforced && useFullRank) {
      // J spans every direction: stationary where r itself is as small as
      // each direction's test asks (a J too singular for the step below
      // leaves the decision to the general path's test).
      freeCount = pd;
      freeStationary = std::sqrt(f) <= scale.perLength;
    } else if (releasedFactor < 0 && noneEnforced && order == JetOrder::Second) {
      freeCount = pd;
      if (lineCount >= 0) {
        freeStationary = FreeParametersStationary(lineCoords, lineCount, grad, scale);
      } else {
        FaceBasis whole;
        BuildFaceBasis(shape, active, &whole);
        freeStationary = IsStationaryOnFace(whole, grad, scale);
      }
    } else if (releasedFactor < 0 && !noneEnforced && order == JetOrder::Second && lineCount >= 0) {
      freeCount = lineCount;
      std::copy(lineCoords, lineCoords + lineCount, freeCoords);
      freeStationary = FreeParametersStationary(freeCoords, freeCount, grad, scale);
    }
    bool finalOnFace = false;
    if (freeCount > 0 && !freeStationary) {
      double step[3];
      if (useFullRank ? FullRankStep(jet, r, pd, size, step)
                      : NewtonStepOver(jet, r, grad, freeCoords, freeCount, ad, step)) {
        const StepOutcome outcome =
            LineSearch(cell, point, active, f, fNoise, limits, g, Eigen::Map<const Vector>(step), true, need,
                       jets.trial, ref);
        if (outcome == StepOutcome::Moved) {
          jets.AcceptTrial(need, ref);
          continue;
        }
        if (outcome == StepOutcome::Blocked) {
          SnapToFace(shape, active, ref);
          jets.valid = false;
          continue;
        }
        if (outcome == StepOutcome::Final) {
          jets.valid = false;
          if (noneEnforced) {
            result.converged = true;
            break;
          }
          // On a face, stationary there: the enforced constraints'
          // multipliers decide below, as after the general path's final step.
          finalOnFace = true;
        }
      }
    }
    if (!finalOnFace) {
      FaceBasis face;
      BuildFaceBasis(shape, active, &face);
      const int m = face.columns;
      const Matrix T = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(&face.t[0][0]);
      const Vector gReduced = T.transpose() * g;
      // The common paths' test above already judged this face (the same
      // iterate and active set) when it found it stationary.
      const bool stationary = m == 0 || (freeCount > 0 && freeStationary) ||
                              (lineCount >= 0 ? FreeParametersStationary(lineCoords, lineCount, grad, scale)
                                              : IsStationaryOnFace(face, grad, scale));
      Vector step = Vector::Zero();
      if (!stationary) {
        Matrix jac = Matrix::Zero();  // rows: ambient coordinates, columns: parameters
        for (int k = 0; k < ad; ++k) {
          for (int i = 0; i < pd; ++i) jac(k, i) = jet.d1[k][i];
        }
        bool haveStep = false;
        if (useFullRank) {
          // 7.3.2.1: J is square; -J^-1 r is always a descent direction.
          Matrix square = jac;
          PadDiagonal(pd, &square);
          if (std::abs(square.determinant()) > kSingularTolerance * std::pow(size, pd)) {
            step = square.partialPivLu().solve(-Eigen::Map<const Vector>(r));
            haveStep = step.allFinite();
          }
        }
        const Matrix gaussNewton = jac.transpose() * jac;
        Matrix gnReduced = T.transpose() * gaussNewton * T;
        // Gradient descent scaled to the Gauss-Newton model's Cauchy step.
        const double curvature = gReduced.dot(gnReduced * gReduced);
        const Vector descent = -gReduced * (gReduced.squaredNorm() / std::max(curvature, 1e-300));
        PadDiagonal(m, &gnReduced);
        if (!haveStep) {
          Matrix hessian = gaussNewton;
          if (order == JetOrder::Second) {
            for (int i = 0; i < pd; ++i) {
              for (int j = 0; j < pd; ++j) {
                for (int k = 0; k < ad; ++k) hessian(i, j) += r[k] * jet.d2[k][i][j];
              }
            }
          }
          const Matrix hReduced = T.transpose() * hessian * T;
          double h[3][3];
          for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) h[i][j] = hReduced(i, j);
          }
          Vector delta;
          if (NewtonStepOf(h, m, gReduced.data(), delta.data())) {
            step = T * delta;
            haveStep = true;
          }
        }
        bool newton = haveStep;
        if (!haveStep) {
          // Levenberg-Marquardt on the Gauss-Newton model: a descent direction
          // for any damping, and well defined for singular Jacobians.
          const double damping = kLevenbergDamping * (gnReduced.trace() + size * size) + 1e-300;
          gnReduced.diagonal().array() += damping;
          Eigen::LLT<Matrix> llt(gnReduced);
          Vector delta = llt.solve(-gReduced);
          if (llt.info() != Eigen::Success || !delta.allFinite() || delta.dot(gReduced) >= 0.0) delta = descent;
          step = T * delta;
        }
        if (releasedFactor >= 0 && MovesOut(shape, releasedFactor, releasedIndex, step.data())) {
          // Right after a release the multiplier promises descent into the
          // interior; a curved model's step back out would only cycle.
          step = T * descent;
          newton = false;
        }
        releasedFactor = -1;

        // The model's step first, then plain descent: a step that the line
        // search cannot use (a nearly singular model) falls back to the gradient.
        const Vector candidates[2] = {step, T * descent};
        bool moved = false, final = false;
        for (int c = 0; c < 2 && !moved && !final; ++c) {
          const StepOutcome outcome =
              LineSearch(cell, point, active, f, fNoise, limits, g, candidates[c], newton && c == 0, need, jets.trial, ref);
          if (outcome == StepOutcome::Rejected || outcome == StepOutcome::Negligible) continue;
          if (outcome == StepOutcome::Moved) {
            jets.AcceptTrial(need, ref);
          } else {
            if (outcome == StepOutcome::Blocked) SnapToFace(shape, active, ref);
            jets.valid = false;
          }
          final = outcome == StepOutcome::Final;
          moved = !final;
        }
        // Otherwise no decrease is possible (or the step was negligible): a
        // stationary point up to rounding, as below.
        if (moved) continue;
      }
    }

    // Stationary on the current face: release the constraint whose
    // multiplier is most negative, if any (algorithm 5, lines 33-45): among
    // those below minus their own tolerance, the steepest per unit of
    // mapped length (DirectionScale).
    int releaseFactor = -1, releaseIndex = -1;
    double steepest = 0.0;
    for (int fac = 0; fac < shape.numFactors(); ++fac) {
      for (int k = 0; k <= shape.factor(fac).dim; ++k) {
        if (!(active.enforced[fac] & (1u << k))) continue;
        double direction[3];
        ReleaseDirection(shape, active, fac, k, direction);
        const double mu = direction[0] * grad[0] + direction[1] * grad[1] + direction[2] * grad[2];
        const double length = std::max(scale.MappedLength(direction), scale.floorLength);
        if (!(mu < -scale.Tolerance(length)) || !(mu / length < steepest)) continue;
        steepest = mu / length;
        releaseFactor = fac;
        releaseIndex = k;
      }
    }
    if (releaseFactor >= 0 && releases < 4 * (pd + 1)) {
      active.enforced[releaseFactor] &= ~(1u << releaseIndex);
      releasedFactor = releaseFactor;
      releasedIndex = releaseIndex;
      ++releases;
      continue;
    }
    result.converged = true;
    break;
  }

  std::copy(ref, ref + pd, result.ref);
  // The last second-order jet, when it lies within a final step of the
  // answer (kFinalStep: far closer than any use of the Hessian needs), gives
  // the Hessian there without another evaluation.
  AnswerModel* model = options.checkKkt ? options.model : nullptr;
  if (model) {
    bool jetNearAnswer = jets.order == JetOrder::Second;
    for (int i = 0; i < pd; ++i) jetNearAnswer = jetNearAnswer && std::abs(jets.at[i] - ref[i]) <= kFinalStep;
    if (jetNearAnswer) {
      DistanceHessian(*jets.atRef, point, pd, ad, model->hessian);
    } else {
      std::fill(&model->hessian[0][0], &model->hessian[0][0] + 9, 0.0);
    }
  }
  const JetOrder finalOrder = options.checkKkt ? JetOrder::First : JetOrder::Value;
  jets.EnsureAt(cell, ref, finalOrder);
  result.kkt = options.checkKkt && result.converged && IsKktPoint(cell, *jets.atRef, point, ref, size);
  std::copy(jets.atRef->x, jets.atRef->x + ad, result.closest);
  if (model) {
    std::copy(&jets.atRef->d1[0][0], &jets.atRef->d1[0][0] + 9, &model->jacobian[0][0]);
    model->known = true;
  } else if (options.model) {
    options.model->known = false;
  }
  result.squaredDistance = SquaredDistance(*jets.atRef, point, ad);
  result.onBoundary = active.enforced[0] != 0 || active.enforced[1] != 0 || active.enforced[2] != 0;
  return result;
}

namespace {

/// True when a coordinate of `value` (<= 1e-12) along whose direction the
/// map moves `length` per unit lies on its face: the map there is within
/// 1e-12 of the cell's `size` of the face's. (A coordinate of 1e-13 next to
/// a weight of 1e12 is a point of its own, not rounding off the face.)
bool OnFace(double value, double length, double size) { return value <= kKktOnFace && value * length <= kKktOnFace * size; }

/// IsKktPoint's test for a cell of line factors, whose parameters are its
/// factors' coordinates: the general test below with its face basis and
/// multipliers written out (the same arithmetic, so the same verdict).
/// Parameter i is held at 0 when it is on that face (OnFace; its
/// multiplier is grad_i), else at 1 when 1 - u_i is (multiplier -grad_i),
/// else free (its basis vector is -e_i / sqrt(2)).
bool IsKktOnUnitBox(const double* ref, const double* grad, const DirectionScale& scale, double size) {
  const double norm = 1.0 / std::sqrt(2.0);
  for (int i = 0; i < scale.paramDim; ++i) {
    const double length = scale.ColumnLength(i);
    if (OnFace(ref[i], length, size)) {
      if (grad[i] < -scale.Tolerance(length)) return false;
    } else if (OnFace(1.0 - ref[i], length, size)) {
      if (-grad[i] < -scale.Tolerance(length)) return false;
    } else if (std::abs(-norm * grad[i]) > scale.Tolerance(norm * length)) {
      return false;
    }
  }
  return true;
}

}  // namespace

bool IsKktPoint(const CellView& cell, const MapJet& jet, const double* point, const double* ref, double size) {
  const CellShape& shape = cell.shape;
  const int pd = shape.paramDim();
  double grad[3] = {0, 0, 0}, r2 = 0.0;
  for (int k = 0; k < cell.ambientDim; ++k) {
    const double r = jet.x[k] - point[k];
    r2 += r * r;
    for (int i = 0; i < pd; ++i) grad[i] += jet.d1[k][i] * r;
  }
  // A converged solve leaves slopes r . J v near rounding; a point that is
  // not stationary along v has one of the order of |J v| |r|. (Square roots
  // apart: r2 times a squared length overflows long before either factor.
  // A tolerance that still overflows would accept any point: not KKT then.)
  const DirectionScale scale{jet, cell.ambientDim, pd, kKktSlope * std::sqrt(r2) + kKktSlopeFloor * size, kThinDirection * size};
  if (!std::isfinite(scale.perLength)) return false;
  if (shape.isBox()) return IsKktOnUnitBox(ref, grad, scale, size);
  ActiveSet active;
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& factor = shape.factor(f);
    double lambda[4];
    FactorBarycentric(shape, f, ref, lambda);
    // lambda_k moves along parameter k - 1; lambda_0 along all of the
    // factor's (the largest of their lengths: the face is held less often).
    double lengths[4] = {0, 0, 0, 0};
    for (int i = 0; i < factor.dim; ++i) {
      double unit[3] = {0, 0, 0};
      unit[factor.offset + i] = 1.0;
      lengths[i + 1] = scale.MappedLength(unit);
      lengths[0] = std::max(lengths[0], lengths[i + 1]);
    }
    for (int k = 0; k <= factor.dim; ++k) {
      if (OnFace(lambda[k], lengths[k], size)) active.enforced[f] |= 1u << k;
    }
    if (active.enforced[f] == (1u << (factor.dim + 1)) - 1) active.enforced[f] &= ~1u;
  }
  FaceBasis face;
  BuildFaceBasis(shape, active, &face);
  if (!IsStationaryOnFace(face, grad, scale)) return false;
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& factor = shape.factor(f);
    for (int k = 0; k <= factor.dim; ++k) {
      if (!(active.enforced[f] & (1u << k))) continue;
      // Releasing lambda_k moves it up and a free lambda_j down. On the
      // face, where the point is stationary, every free j gives the same
      // derivative up to the tolerance: the one whose direction the map
      // stretches least judges it most finely (a free coordinate next to a
      // heavy weight would lend the test its scale).
      double slope = 0.0, tolerance = -1.0;
      for (int j = 0; j <= factor.dim; ++j) {
        if (active.enforced[f] & (1u << j)) continue;
        double release[3] = {0, 0, 0};
        if (k > 0) release[factor.offset + k - 1] += 1.0;
        if (j > 0) release[factor.offset + j - 1] -= 1.0;
        const double candidate = scale.Tolerance(scale.MappedLength(release));
        if (tolerance < 0.0 || candidate < tolerance) {
          tolerance = candidate;
          slope = 0.0;
          for (int i = 0; i < pd; ++i) slope += release[i] * grad[i];
        }
      }
      if (slope < -tolerance) return false;
    }
  }
  return true;
}

}  // namespace invmap::kernels
