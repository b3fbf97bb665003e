#include "engine/walk_start_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace invmap::engine {
namespace {

/// Grid cells per walkable cell, and the most grid cells.
constexpr double kGridCellsPerCell = 27.0;
constexpr std::int64_t kMaxGridCells = std::int64_t{1} << 24;

/// Passes of FillEmptyFromNeighbors.
constexpr int kFillPasses = 2;

/// How well `solver`'s cell suits as the start for points near `centre`,
/// a point of its control-point box: above 1 for a tetrahedron whose corner
/// tetrahedron holds it (1 + its least corner barycentric, so the deepest
/// wins), below 0 for one that does not; in [0, 1] for other cells, by how
/// centred on their box it lies (1 at the box's centre).
double StartScore(const kernels::CellSolver& solver, const double* centre) {
  if (solver.isTetrahedron()) {
    double lambda[4];
    if (!solver.CornerBarycentric(centre, lambda)) return -std::numeric_limits<double>::infinity();
    const double least = *std::min_element(lambda, lambda + 4);
    return least >= 0.0 ? 1.0 + least : least;
  }
  double offCentre = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double half = 0.5 * (solver.boxHi()[k] - solver.boxLo()[k]);
    const double mid = 0.5 * (solver.boxHi()[k] + solver.boxLo()[k]);
    if (half > 0.0) offCentre = std::max(offCentre, std::abs(centre[k] - mid) / half);
  }
  return 1.0 - std::min(offCentre, 1.0);
}

}  // namespace

void WalkStartGrid::Build(const std::vector<kernels::CellSolver>& solvers, const std::vector<bool>& walkable) {
  cells_.clear();
  if (solvers.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) return;
  double hi[3];
  std::int64_t walkableCount = 0;
  for (std::size_t c = 0; c < solvers.size(); ++c) {
    if (!walkable[c]) continue;
    for (int k = 0; k < 3; ++k) {
      lo_[k] = walkableCount == 0 ? solvers[c].boxLo()[k] : std::min(lo_[k], solvers[c].boxLo()[k]);
      hi[k] = walkableCount == 0 ? solvers[c].boxHi()[k] : std::max(hi[k], solvers[c].boxHi()[k]);
    }
    ++walkableCount;
  }
  if (walkableCount == 0) return;
  double extent[3], volume = 1.0, largest = 0.0;
  for (int k = 0; k < 3; ++k) {
    extent[k] = hi[k] - lo_[k];
    if (!std::isfinite(extent[k])) return;
    largest = std::max(largest, extent[k]);
  }
  if (!(largest > 0.0)) return;
  // Cubic grid cells of about kGridCellsPerCell per cell over the box (a
  // flat extent counted as a thousandth of the largest), widened until the
  // grid fits its bound.
  for (int k = 0; k < 3; ++k) volume *= std::max(extent[k], 1e-3 * largest);
  double step = std::cbrt(volume / (kGridCellsPerCell * static_cast<double>(walkableCount)));
  for (;;) {
    std::int64_t total = 1;
    for (int k = 0; k < 3; ++k) {
      count_[k] = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::ceil(extent[k] / step)), 1, kMaxGridCells);
      total = std::min(total * count_[k], kMaxGridCells + 1);
    }
    if (total <= kMaxGridCells) break;
    step *= 1.25;
  }
  double stepOf[3];
  for (int k = 0; k < 3; ++k) {
    stepOf[k] = extent[k] > 0.0 ? extent[k] / static_cast<double>(count_[k]) : 1.0;
    inverseStep_[k] = 1.0 / stepOf[k];
  }
  for (int k = 0; k < 3; ++k) tiles_[k] = (count_[k] + 3) / 4;
  cells_.assign(static_cast<std::size_t>(tiles_[0] * tiles_[1] * tiles_[2] * 64), -1);
  std::vector<double> score(cells_.size(), -std::numeric_limits<double>::infinity());
  // Every grid centre within a cell's box scores that cell; cells in index
  // order and a strict improvement keep the lowest index on a tie.
  for (std::size_t c = 0; c < solvers.size(); ++c) {
    if (!walkable[c]) continue;
    const kernels::CellSolver& solver = solvers[c];
    std::int64_t first[3], last[3];
    bool empty = false;
    for (int k = 0; k < 3; ++k) {
      first[k] = std::max<std::int64_t>(0, static_cast<std::int64_t>(std::ceil((solver.boxLo()[k] - lo_[k]) * inverseStep_[k] - 0.5)));
      last[k] = std::min<std::int64_t>(count_[k] - 1,
                                       static_cast<std::int64_t>(std::floor((solver.boxHi()[k] - lo_[k]) * inverseStep_[k] - 0.5)));
      empty = empty || first[k] > last[k];
    }
    if (empty) continue;
    for (std::int64_t z = first[2]; z <= last[2]; ++z) {
      for (std::int64_t y = first[1]; y <= last[1]; ++y) {
        for (std::int64_t x = first[0]; x <= last[0]; ++x) {
          const std::int64_t at[3] = {x, y, z};
          double centre[3];
          for (int k = 0; k < 3; ++k) centre[k] = lo_[k] + (static_cast<double>(at[k]) + 0.5) * stepOf[k];
          const std::size_t index = Slot(x, y, z);
          const double s = StartScore(solver, centre);
          if (s > score[index]) {
            score[index] = s;
            cells_[index] = static_cast<std::int32_t>(c);
          }
        }
      }
    }
  }
  FillEmptyFromNeighbors();
}

void WalkStartGrid::FillEmptyFromNeighbors() {
  for (int pass = 0; pass < kFillPasses; ++pass) {
    const std::vector<std::int32_t> before = cells_;
    for (std::int64_t z = 0; z < count_[2]; ++z) {
      for (std::int64_t y = 0; y < count_[1]; ++y) {
        for (std::int64_t x = 0; x < count_[0]; ++x) {
          const std::size_t index = Slot(x, y, z);
          if (before[index] >= 0) continue;
          for (int k = 0; k < 3 && cells_[index] < 0; ++k) {
            for (int side : {-1, 1}) {
              std::int64_t next[3] = {x, y, z};
              next[k] += side;
              if (next[k] < 0 || next[k] >= count_[k]) continue;
              const std::int32_t cell = before[Slot(next[0], next[1], next[2])];
              if (cell >= 0) {
                cells_[index] = cell;
                break;
              }
            }
          }
        }
      }
    }
  }
}

}  // namespace invmap::engine
