#include "engine/warm_start.h"

#include <algorithm>
#include <cmath>

#include "engine/analytic_start.h"
#include "kernels/cramer.h"

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

}  // namespace

bool SolveFree(const double (*model)[3], const double* rhs, int paramDim, const bool* held, double* step) {
  int free[3], m = 0;
  for (int i = 0; i < paramDim; ++i) {
    if (!held[i]) free[m++] = i;
  }
  double a[3][3], b[3];
  for (int r = 0; r < m; ++r) {
    b[r] = rhs[free[r]];
    for (int j = 0; j < paramDim; ++j) b[r] -= held[j] ? model[free[r]][j] * step[j] : 0.0;
    for (int c = 0; c < m; ++c) a[r][c] = model[free[r]][free[c]];
  }
  double x[3];
  if (m == 1) {
    if (!(a[0][0] > 0.0)) return false;
    x[0] = b[0] / a[0][0];
  } else if (m == 2) {
    const double det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    if (!(a[0][0] > 0.0 && det > 0.0)) return false;
    const double inverse = 1.0 / det;
    x[0] = (a[1][1] * b[0] - a[0][1] * b[1]) * inverse;
    x[1] = (a[0][0] * b[1] - a[1][0] * b[0]) * inverse;
  } else if (m == 3) {
    const double det = kernels::Determinant3(a[0], a[1], a[2]);
    if (!(a[0][0] > 0.0 && a[0][0] * a[1][1] - a[0][1] * a[1][0] > 0.0 && det > 0.0)) return false;
    // Symmetric: the rows serve as the columns Cramer's rule takes.
    kernels::CramerSolve3(a[0], a[1], a[2], det, b, x);
  }
  for (int r = 0; r < m; ++r) step[free[r]] = x[r];
  return std::isfinite(step[0]) && std::isfinite(step[1]) && std::isfinite(step[2]);
}


void PredictStart(const CellStore& store, const WarmStart& warm, const double* p, std::int64_t* cell, double* ref) {
  *cell = warm.cell;
  for (int i = 0; i < 3; ++i) ref[i] = warm.ref[i];
  if (warm.cell >= 0 && PredictOnElementarySurface(store, warm, p, cell, ref)) return;
  if (warm.cell < 0 || !warm.model.known) return;
  const int dim = store.dimension();
  if (std::equal(p, p + dim, warm.point)) return;
  const kernels::CellShape& shape = store.shape(warm.cell);
  const int paramDim = shape.paramDim();
  const bool box = shape.isBox();
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
  const CellOrigin from = store.origin(warm.cell);
  const CellOrigin to = store.origin(next);
  for (int i = 0; i < paramDim; ++i) {
    ref[i] = (from.paramLo[i] + from.paramScale[i] * ref[i] - to.paramLo[i]) / to.paramScale[i];
  }
  *cell = next;
}

}  // namespace invmap::engine
