#include "engine/warm_start.h"

#include <algorithm>
#include <cmath>

namespace invmap::engine {
namespace {

/// The model of half the squared distance to `p` near the previous answer
/// x, over the paramDim x paramDim block of `model`. Its Hessian there is
/// J^T J + C(x - p), with C(r) = sum_k r_k d2x_k linear in r; the previous
/// point's model gives C(x - previous). The residual at the foot is nearly
/// normal to the geometry, so C(x - p) is taken as that scaled by the share
/// of x - p along x - previous. `gaussNewton` receives J^T J alone.
void StepModels(const WarmStart& warm, int paramDim, int dim, const double* p, double (*model)[3],
                double (*gaussNewton)[3]) {
  const kernels::AnswerModel& m = warm.model;
  double along = 0.0, previous2 = 0.0;
  for (int k = 0; k < dim; ++k) {
    along += (warm.closest[k] - p[k]) * (warm.closest[k] - warm.point[k]);
    previous2 += (warm.closest[k] - warm.point[k]) * (warm.closest[k] - warm.point[k]);
  }
  // A zero Hessian is an unknown one (the solve evaluated no second
  // derivatives near the answer): J^T J alone then.
  const double scale = previous2 > 0.0 && m.hessian[0][0] != 0.0 ? along / previous2 : 0.0;
  for (int i = 0; i < paramDim; ++i) {
    for (int j = 0; j < paramDim; ++j) {
      double jtj = 0.0;
      for (int k = 0; k < dim; ++k) jtj += m.jacobian[k][i] * m.jacobian[k][j];
      gaussNewton[i][j] = jtj;
      model[i][j] = scale == 0.0 ? jtj : jtj + scale * (m.hessian[i][j] - jtj);
    }
  }
}

/// Solves model step = rhs for the parameters not `held` (the held ones
/// keep their `step`, which moves the right-hand side), by Cholesky on the
/// free block. False when that block is not positive definite.
bool SolveFree(const double (*model)[3], const double* rhs, int paramDim, const bool* held, double* step) {
  int free[3], m = 0;
  for (int i = 0; i < paramDim; ++i) {
    if (!held[i]) free[m++] = i;
  }
  double b[3], l[3][3];
  for (int a = 0; a < m; ++a) {
    b[a] = rhs[free[a]];
    for (int j = 0; j < paramDim; ++j) b[a] -= held[j] ? model[free[a]][j] * step[j] : 0.0;
  }
  for (int a = 0; a < m; ++a) {
    for (int c = 0; c <= a; ++c) {
      double sum = model[free[a]][free[c]];
      for (int e = 0; e < c; ++e) sum -= l[a][e] * l[c][e];
      if (a == c) {
        if (!(sum > 0.0)) return false;
        l[a][a] = std::sqrt(sum);
      } else {
        l[a][c] = sum / l[c][c];
      }
    }
  }
  double y[3];
  for (int a = 0; a < m; ++a) {
    y[a] = b[a];
    for (int e = 0; e < a; ++e) y[a] -= l[a][e] * y[e];
    y[a] /= l[a][a];
  }
  for (int a = m - 1; a >= 0; --a) {
    for (int e = a + 1; e < m; ++e) y[a] -= l[e][a] * y[e];
    y[a] /= l[a][a];
    step[free[a]] = y[a];
  }
  return std::isfinite(step[0]) && std::isfinite(step[1]) && std::isfinite(step[2]);
}

/// True when every factor of the cell is an interval: its reference domain
/// is the unit box, one bound pair per parameter.
bool IsBoxCell(const kernels::CellShape& shape) {
  for (int f = 0; f < shape.numFactors(); ++f) {
    if (shape.factor(f).dim != 1) return false;
  }
  return true;
}

}  // namespace

void PredictStart(const CellStore& store, const WarmStart& warm, const double* p, std::int64_t* cell, double* ref) {
  *cell = warm.cell;
  std::copy(warm.ref, warm.ref + 3, ref);
  if (warm.cell < 0 || !warm.model.known) return;
  const int dim = store.dimension();
  if (std::equal(p, p + dim, warm.point)) return;
  const kernels::CellShape& shape = store.solver(warm.cell).cell().shape;
  const int paramDim = shape.paramDim();
  const bool box = IsBoxCell(shape);
  double model[3][3], gaussNewton[3][3], rhs[3] = {0, 0, 0};
  StepModels(warm, paramDim, dim, p, model, gaussNewton);
  for (int i = 0; i < paramDim; ++i) {
    for (int k = 0; k < dim; ++k) rhs[i] += warm.model.jacobian[k][i] * (p[k] - warm.closest[k]);
  }
  bool held[3] = {false, false, false};
  double step[3] = {0, 0, 0};
  // A step out of the geometry (past an edge of the cell that no span
  // continues) is held on that edge, and the others re-solved: the foot of
  // a point beyond a patch's edge slides along the edge, and the free step
  // would turn the point's height over a tilted tangent plane into a slide.
  // Gauss-Newton where the model is not positive definite.
  for (int attempt = 0; attempt <= paramDim; ++attempt) {
    if (!SolveFree(model, rhs, paramDim, held, step) && !SolveFree(gaussNewton, rhs, paramDim, held, step)) return;
    bool heldMore = false;
    for (int i = 0; box && i < paramDim; ++i) {
      const double to = warm.ref[i] + step[i];
      if (held[i] || (to >= 0.0 && to <= 1.0)) continue;
      int across[3] = {0, 0, 0};
      across[i] = to < 0.0 ? -1 : 1;
      if (store.SplineNeighbor(warm.cell, across) >= 0) continue;
      held[i] = heldMore = true;
      step[i] = std::clamp(to, 0.0, 1.0) - warm.ref[i];
    }
    if (!heldMore) break;
  }
  for (int i = 0; i < paramDim; ++i) ref[i] += step[i];

  // Out of a B-spline cell's unit box: the span the step points into.
  int across[3] = {0, 0, 0};
  bool leaves = false;
  for (int i = 0; box && i < paramDim; ++i) {
    across[i] = ref[i] < 0.0 ? -1 : ref[i] > 1.0 ? 1 : 0;
    leaves = leaves || across[i] != 0;
  }
  if (!leaves) return;
  const std::int64_t next = store.SplineNeighbor(warm.cell, across);
  if (next < 0 || store.inRegion(next)) return;
  const CellOrigin& from = store.origin(warm.cell);
  const CellOrigin& to = store.origin(next);
  for (int i = 0; i < paramDim; ++i) {
    ref[i] = (from.paramLo[i] + from.paramScale[i] * ref[i] - to.paramLo[i]) / to.paramScale[i];
  }
  *cell = next;
}

}  // namespace invmap::engine
