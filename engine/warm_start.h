// The start of a point's first cell solve, predicted from the previous
// point's answer. Points come in Morton order, so the previous answer is
// usually a short step along the geometry from this point's foot; one
// Gauss-Newton step from it (with the Jacobian that answer's solve already
// evaluated) lands closer still, often in the next span of a B-spline patch.
#pragma once

#include <cstdint>

#include "engine/cell_store.h"

namespace invmap::engine {

/// The previous point's answer, kept for the next point of the bucket.
struct WarmStart {
  std::int64_t cell = -1;       ///< -1: none (the first point of a bucket).
  double point[3] = {0, 0, 0};  ///< The query point it answered.
  double ref[3] = {0, 0, 0};    ///< Reference coordinates in `cell`.
  double closest[3] = {0, 0, 0};
  double jacobian[3][3] = {};  ///< dx_k/du_i at ref; zero when unknown.
};

/// Where `p`'s search starts: the cell and reference coordinates one
/// Gauss-Newton step from `warm` predicts for its foot. A step out of a
/// B-spline cell moves to the neighbouring span it points into (at most one
/// per direction; not into an affine region, which the search solves as a
/// block). The start may lie outside the cell's domain: the local solve
/// clamps it. Without a Jacobian, and for a repeat of the previous point
/// (which then gets its answer back bit for bit), the start is `warm` itself.
void PredictStart(const CellStore& store, const WarmStart& warm, const double* p, std::int64_t* cell, double* ref);

}  // namespace invmap::engine
