// The affine hexahedra of a volume mesh (parallelepipeds: every linear
// hexahedron of a sheared or scaled structured grid, and a higher-order one
// on straight sides) as the walk through the mesh reads them: per cell one
// record of two cache lines with its frame (the corner at the reference
// origin and the edges to the unit points, CellSolver::FrameCoordinates'
// columns), its distance tolerance and its face neighbours. A step of the
// walk through such a cell reads nothing else: its solver and control
// points, scattered over other lines and a cache miss each on random
// points, are read only when the closed form cannot decide (a point within
// rounding of the cell's boundary, or an ill-conditioned frame).
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/cell_solver.h"

namespace invmap::engine {

/// One affine hexahedron, aligned to its two cache lines.
struct alignas(64) HexFrame {
  double origin[3];
  double edge[3][3];  ///< edge[i]: the corner at unit point i less the origin
  /// The cell's inside tolerance squared, (kDistanceTolerance * size)^2; a
  /// NaN marks a cell with no frame (not an affine hexahedron).
  double tau2;
  std::int32_t neighbors[6];  ///< FaceAdjacency::Neighbor(cell, face), face 0 .. 5
};
static_assert(sizeof(HexFrame) == 128, "a frame is two cache lines");

/// What the frame says of a point (HexFrames::Locate).
enum class FrameVerdict {
  Inside,   ///< the point is in the cell: its reference coordinates are exact
  Outside,  ///< beyond the cell: the reference coordinates name the faces to leave by
  Unsure,   ///< within rounding of the boundary, or rounding too large: ask the solver
};

class HexFrames {
 public:
  /// Frames for the affine hexahedra among `solvers` whose frame is
  /// invertible, with their neighbours as `neighbor(cell, face)` gives them;
  /// nothing when such cells are under half the cells (a frame per cell is
  /// 128 bytes: on a mesh of tetrahedra with a few hexahedra it would cost
  /// more memory than it saves time).
  template <typename NeighborOf>
  void Build(const std::vector<kernels::CellSolver>& solvers, const NeighborOf& neighbor) {
    frames_.clear();
    std::size_t count = 0;
    for (const kernels::CellSolver& solver : solvers) count += IsFramed(solver) ? 1 : 0;
    if (count == 0 || 2 * count < solvers.size()) return;
    frames_.resize(solvers.size());
    for (std::size_t c = 0; c < solvers.size(); ++c) {
      if (!Fill(solvers[c], &frames_[c])) continue;
      for (int f = 0; f < 6; ++f) {
        frames_[c].neighbors[f] = static_cast<std::int32_t>(neighbor(static_cast<std::int64_t>(c), f));
      }
    }
  }

  bool empty() const { return frames_.empty(); }

  /// The frame of `cell`, or null when it has none.
  const HexFrame* Of(std::int64_t cell) const {
    if (frames_.empty()) return nullptr;
    const HexFrame& frame = frames_[static_cast<std::size_t>(cell)];
    return frame.tau2 == frame.tau2 ? &frame : nullptr;
  }

  /// Requests `cell`'s record from memory (both lines).
  void Prefetch(std::int64_t cell) const {
    if (frames_.empty()) return;
    const char* at = reinterpret_cast<const char*>(&frames_[static_cast<std::size_t>(cell)]);
    __builtin_prefetch(at);
    __builtin_prefetch(at + 64);
  }

  /// The point's reference coordinates (result->ref) in the frame's cell,
  /// as CellSolver::FrameCoordinates computes them (the same bits), and the
  /// verdict SolveInside would reach on them: Inside, with `result` as
  /// SolveInside fills it (the closest point the frame's map, not the
  /// cell's, a rounding apart), when they lie in the domain and the frame's
  /// map there is the point to half the cell's tolerance (the other half
  /// covers how far an affine cell's map may stray from its frame's,
  /// kAffineCellTolerance, so SolveInside would say inside too); Outside
  /// when they lie beyond the domain by more than kHullSlack; Unsure
  /// otherwise (result->ref then not meaningful).
  static FrameVerdict Locate(const HexFrame& frame, const double* point, kernels::CellSolveResult* result);

  /// The faces (as kernels::FacesAt) an Outside point's reference
  /// coordinates lie beyond, most negative first; their count.
  static int ExitFaces(const double* ref, int* faces);

  std::size_t MemoryBytes() const { return frames_.capacity() * sizeof(HexFrame); }

 private:
  /// True for an affine full-rank hexahedron (FrameCoordinates' cells).
  static bool IsFramed(const kernels::CellSolver& solver);
  /// Fills `frame` (neighbours aside) for `solver`; false (and a NaN
  /// tau2) when it is no framed cell or its frame is flat.
  static bool Fill(const kernels::CellSolver& solver, HexFrame* frame);

  std::vector<HexFrame> frames_;  ///< per cell (when any)
};

}  // namespace invmap::engine
