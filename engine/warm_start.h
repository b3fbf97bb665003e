// The start of a point's first cell solve, predicted from the previous
// point's answer. Points come in Morton order, so the previous answer is
// usually a short step along the geometry from this point's foot; one Newton
// step from it (with the derivatives that answer's solve already evaluated)
// lands closer still, often in the next span of a B-spline patch.
#pragma once

#include <cstdint>

#include "engine/cell_store.h"
#include "kernels/local_solver.h"

namespace invmap::engine {

/// The previous point's answer, kept for the next point of the bucket.
struct WarmStart {
  std::int64_t cell = -1;       ///< -1: none (the first point of a bucket).
  double point[3] = {0, 0, 0};  ///< The query point it answered.
  double ref[3] = {0, 0, 0};    ///< Reference coordinates in `cell`.
  double closest[3] = {0, 0, 0};
  kernels::AnswerModel model;  ///< The local model at ref, when known.
};

/// Where `p`'s search starts: the cell and reference coordinates one Newton
/// step from `warm` predicts for its foot. The step uses `warm`'s Hessian
/// (the previous point's: the points are close), or Gauss-Newton's J^T J
/// where that is unknown or not positive definite. A step past an edge of
/// the geometry is held on that edge; a step out of a B-spline cell moves to
/// the neighbouring span it points into (at most one per direction; not into
/// an affine region, which the search solves as a block). The start may lie
/// outside the cell's domain: the local solve clamps it. Without a model,
/// and for a repeat of the previous point (which then gets its answer back
/// bit for bit), the start is `warm` itself.
void PredictStart(const CellStore& store, const WarmStart& warm, const double* p, std::int64_t* cell, double* ref);

/// Solves model step = rhs (paramDim x paramDim, row-major in 3 x 3) for the
/// parameters not `held`; the held ones keep their `step`, which moves the
/// right-hand side. Closed form for the free block of at most 3 x 3. False
/// when that block is not positive definite (by its leading minors) or the
/// step is not finite. With rhs = 0 and a local model's Hessian: the model's
/// least value with the held parameters displaced by their step.
bool SolveFree(const double (*model)[3], const double* rhs, int paramDim, const bool* held, double* step);

}  // namespace invmap::engine
