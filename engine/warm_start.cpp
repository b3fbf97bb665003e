#include "engine/warm_start.h"

#include <algorithm>
#include <cmath>

#include "kernels/cramer.h"

namespace invmap::engine {
namespace {

/// The Gauss-Newton step: the least-squares solution of J step = p - x, from
/// the normal equations (J^T J is at most 3 x 3). False when J^T J is
/// singular or the step is not finite (J unknown, a collapsed edge).
bool GaussNewtonStep(const WarmStart& warm, int paramDim, int dim, const double* p, double* step) {
  double normal[3][3] = {}, rhs[3] = {0, 0, 0};
  for (int i = 0; i < paramDim; ++i) {
    for (int k = 0; k < dim; ++k) rhs[i] += warm.jacobian[k][i] * (p[k] - warm.closest[k]);
    for (int j = 0; j < paramDim; ++j) {
      for (int k = 0; k < dim; ++k) normal[i][j] += warm.jacobian[k][i] * warm.jacobian[k][j];
    }
  }
  // Unused parameters get an identity row: the 3 x 3 solve covers every case.
  for (int i = paramDim; i < 3; ++i) normal[i][i] = 1.0;
  const double det = kernels::Determinant3(normal[0], normal[1], normal[2]);
  if (!(std::abs(det) > 0.0)) return false;
  kernels::CramerSolve3(normal[0], normal[1], normal[2], det, rhs, step);
  return std::isfinite(step[0]) && std::isfinite(step[1]) && std::isfinite(step[2]);
}

}  // namespace

void PredictStart(const CellStore& store, const WarmStart& warm, const double* p, std::int64_t* cell, double* ref) {
  *cell = warm.cell;
  std::copy(warm.ref, warm.ref + 3, ref);
  if (warm.cell < 0) return;
  const int dim = store.dimension();
  if (std::equal(p, p + dim, warm.point)) return;
  const int paramDim = store.solver(warm.cell).cell().shape.paramDim();
  double step[3];
  if (!GaussNewtonStep(warm, paramDim, dim, p, step)) return;
  for (int i = 0; i < paramDim; ++i) ref[i] += step[i];

  // Out of a B-spline cell's unit box: the span the step points into.
  int across[3] = {0, 0, 0};
  bool leaves = false;
  for (int i = 0; i < paramDim; ++i) {
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
