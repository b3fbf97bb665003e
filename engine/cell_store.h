// The cells of a manifold: every patch turned into Bezier cells, with their
// solvers (bounds, precomputed distance nets) and the way back to the patch.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "engine/check.h"
#include "invmap/invmap.h"
#include "kernels/cell_solver.h"

namespace invmap::engine {

/// Where a cell came from and how its reference coordinates map to the
/// parameters reported for it: param_i = paramLo[i] + paramScale[i] * ref_i
/// (knot values for B-spline cells; identity for Bezier and mesh cells).
struct CellOrigin {
  std::int32_t patch = 0;
  std::int64_t indexInPatch = 0;
  double paramLo[3] = {0, 0, 0};
  double paramScale[3] = {1, 1, 1};
};

/// All cells of a geometry. Immutable after Build; safe to read from many threads.
class CellStore {
 public:
  /// Validates `geometry` and builds its cells. Returns an empty string on
  /// success, otherwise a message naming the patch and the field
  /// ("patch 3: cells[12]: vertex index 99 out of range [0, 40)").
  /// `maxThreads` bounds the threads used to precompute the cells (0 = all).
  std::string Build(const Geometry& geometry, int maxThreads);

  int dimension() const { return dimension_; }
  std::int64_t size() const { return static_cast<std::int64_t>(solvers_.size()); }
  const kernels::CellSolver& solver(std::int64_t cell) const {
    INVMAP_ASSERT(cell >= 0 && cell < size(), "cell " << cell << " not in [0, " << size() << ")");
    return solvers_[cell];
  }
  const CellOrigin& origin(std::int64_t cell) const {
    INVMAP_ASSERT(cell >= 0 && cell < size(), "cell " << cell << " not in [0, " << size() << ")");
    return origins_[cell];
  }
  std::size_t numPatches() const { return numPatches_; }
  /// True when some cell is a volume (paramDim == dimension), whose exact
  /// inside hits the search tries first.
  bool hasVolumeCells() const { return hasVolumeCells_; }
  /// Index of the first cell of `patch` (cells of a patch are contiguous);
  /// patchFirstCell(numPatches()) == size().
  std::int64_t patchFirstCell(std::size_t patch) const { return patchFirst_[patch]; }
  /// Heap memory of the cells: control points, weights, solvers and their nets.
  std::size_t MemoryBytes() const;

 private:
  /// Appends one Bezier cell (control points copied) and its origin.
  void AddCell(const kernels::CellShape& shape, const double* points, const double* weights,
               const CellOrigin& origin);

  int dimension_ = 3;
  std::size_t numPatches_ = 0;
  bool hasVolumeCells_ = false;
  std::vector<std::int64_t> patchFirst_;  // numPatches_ + 1 entries
  std::vector<kernels::CellShape> shapes_;
  std::vector<std::int64_t> pointOffset_;   // first coordinate of each cell in points_
  std::vector<std::int64_t> weightOffset_;  // first weight of each cell in weights_, -1 if polynomial
  std::vector<double> points_;
  std::vector<double> weights_;
  std::vector<CellOrigin> origins_;
  std::vector<kernels::CellSolver> solvers_;  // built last: they point into points_ and weights_
};

/// Converts the public cell type to the kernels' one.
kernels::CellType ToKernelType(CellType type);

}  // namespace invmap::engine
