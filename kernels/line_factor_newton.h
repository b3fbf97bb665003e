// The fast path of the local solve: Newton iterations with the dimensions
// fixed at compile time, for curves and surfaces of line factors (lines and
// quads in a higher-dimensional space) in their common case.
#pragma once

#include "kernels/active_set.h"
#include "kernels/cell_map.h"
#include "kernels/jet_cache.h"
#include "kernels/local_solver.h"

namespace invmap::kernels {

/// How LineFactorNewton left the solve.
enum class FastOutcome { Converged, AboveLevel, Handover };

/// The fast path from `ref` with the active set `active` (LineFactorNewton in
/// line_factor_newton.cpp, for the cell's dimensions): Converged or
/// AboveLevel ends the local solve (`result` filled as LocalSolve fills it);
/// Handover leaves `ref`, `jets` and `*iter` where LocalSolve's general loop
/// goes on. Handover at once for cells it does not cover (a volume, a
/// simplex factor, an affine map).
FastOutcome LineFactorNewtonFor(const CellView& cell, const double* point, const LocalSolveOptions& options,
                                const ActiveSet& active, double* ref, JetCache* jets, bool* exclusionPending,
                                int* iter, LocalSolveResult* result);

}  // namespace invmap::kernels
