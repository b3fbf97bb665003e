// Local minima on trimmed faces (CAD models): whether a point that a cell
// of a trimmed face holds is a local minimum of the distance to another
// point as far as that face says. Inside the face's region that is the
// cell's own KKT test; on the region's boundary (an edge) the distance must
// also grow into the face, or fall only toward the part its loops trim
// away. The enumerations of every local minimum (engine/local_minima.cpp,
// engine/model_minima.cpp) ask it of every cell holding a minimum's point.
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "engine/cell_store.h"
#include "kernels/cell_solver.h"

namespace invmap::engine {

/// The cells of the face of edge cell `edgeCell` (a trimmed surface's
/// edge) whose knot boxes hold the edge's pcurve (u, v) at reference
/// coordinate `ref`, with the reference coordinates of (u, v) on each.
std::vector<std::pair<std::int64_t, std::array<double, 3>>> FaceCellsAtEdgePoint(const CellStore& store,
                                                                                std::int64_t edgeCell,
                                                                                const double* ref);

/// True when `cell` holds the point x (the store's frame) within
/// `tolerance`, with x's reference coordinates in *ref. A trimmed face's
/// cell answers only points of its region, and an edge is a curve cell of
/// one of the faces that meet there only: a point of another face's
/// boundary is found on that face's surface, untrimmed, within
/// `edgeTolerance` (a model's edges lie within its tolerance of their
/// faces), and held where the region reaches it.
bool HoldsPoint(const CellStore& store, std::int64_t cell, const double* x, double tolerance, double edgeTolerance,
                kernels::SolveWorkspace* ws, double* ref);

/// True when the point at `ref` of `cell` may be a local minimum of the
/// distance to `point` (the store's frame) on the cell's surface: a KKT
/// point of the cell's box (kernels/kkt_point.h), or, on a trimmed face's
/// cell, a point where the distance falls only toward the outside of the
/// face's region (a point of its boundary). For an edge cell of a trimmed
/// face: its own KKT test, and this test on every cell of its face that
/// holds the point (FaceCellsAtEdgePoint).
bool MinimumOnCell(const CellStore& store, std::int64_t cell, const double* ref, const double* point);

}  // namespace invmap::engine
