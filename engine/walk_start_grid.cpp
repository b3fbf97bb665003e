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

/// How well a cell suits as the start for points near `centre`, a point of
/// its control-point box: above 1 for a tetrahedron whose corner
/// tetrahedron holds it, or an affine hexahedron or wedge that holds it (1
/// + its least barycentric, so the deepest wins), below 0 for one that
/// does not; in [0, 1] for other cells, by how centred on their box it lies
/// (1 at the box's centre). A tetrahedron's
/// corner map is inverted once for all the centres in its box.
class StartScore {
 public:
  explicit StartScore(const kernels::CellSolver& solver)
      : solver_(solver), framed_(!solver.isTetrahedron() && solver.isAffine() && solver.isFullRank()) {
    if (!solver.isTetrahedron()) return;
    origin_ = solver.CornerPoint(0);
    double e[3][3];  // columns: the edges from corner 0
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) e[k][i] = solver.CornerPoint(i + 1)[k] - origin_[k];
    }
    const double det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                       e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                       e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
    if (!(std::abs(det) > 0.0)) return;
    // The inverse by the adjugate.
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) {
        const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, k1 = (k + 1) % 3, k2 = (k + 2) % 3;
        inverse_[i][k] = (e[k1][i1] * e[k2][i2] - e[k1][i2] * e[k2][i1]) / det;
      }
    }
    tetrahedron_ = true;
  }

  /// Narrows [*first, *last], the grid centres centre0 + x * (stepX, 0, 0)
  /// of one row within the box, to those a tetrahedron may hold (its
  /// barycentric coordinates are linear along the row; a centre of slack
  /// kept on each side, which operator() then scores exactly); other cells
  /// keep the whole row.
  void NarrowRow(const double* centre0, double stepX, std::int64_t* first, std::int64_t* last) const {
    if (!tetrahedron_) return;
    double a[4], b[4];  // lambda_i = a_i + b_i * x
    a[0] = 1.0;
    b[0] = 0.0;
    for (int i = 0; i < 3; ++i) {
      a[i + 1] = 0.0;
      for (int k = 0; k < 3; ++k) a[i + 1] += inverse_[i][k] * (centre0[k] - origin_[k]);
      b[i + 1] = inverse_[i][0] * stepX;
      a[0] -= a[i + 1];
      b[0] -= b[i + 1];
    }
    double lo = static_cast<double>(*first), hi = static_cast<double>(*last);
    for (int i = 0; i < 4; ++i) {
      if (b[i] > 0.0) {
        lo = std::max(lo, -a[i] / b[i]);
      } else if (b[i] < 0.0) {
        hi = std::min(hi, -a[i] / b[i]);
      } else if (a[i] < 0.0) {
        hi = lo - 3.0;  // never inside along this row
      }
    }
    if (!(lo <= hi + 2.0)) {
      *last = *first - 1;
      return;
    }
    *first = std::max(*first, static_cast<std::int64_t>(std::floor(lo)) - 1);
    *last = std::min(*last, static_cast<std::int64_t>(std::ceil(hi)) + 1);
  }

  double operator()(const double* centre) const {
    if (solver_.isTetrahedron()) {
      if (!tetrahedron_) return -std::numeric_limits<double>::infinity();
      double lambda[4], w[3];
      for (int k = 0; k < 3; ++k) w[k] = centre[k] - origin_[k];
      lambda[0] = 1.0;
      for (int i = 0; i < 3; ++i) {
        lambda[i + 1] = inverse_[i][0] * w[0] + inverse_[i][1] * w[1] + inverse_[i][2] * w[2];
        lambda[0] -= lambda[i + 1];
      }
      const double least = *std::min_element(lambda, lambda + 4);
      return least >= 0.0 ? 1.0 + least : least;
    }
    if (framed_) {
      // A parallelepiped (or straight wedge) holds the centre when its
      // preimage lies in the domain: scored as a tetrahedron.
      const double least = solver_.InsideScore(centre);
      return least >= 0.0 ? 1.0 + least : least;
    }
    double offCentre = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double half = 0.5 * (solver_.boxHi()[k] - solver_.boxLo()[k]);
      const double mid = 0.5 * (solver_.boxHi()[k] + solver_.boxLo()[k]);
      if (half > 0.0) offCentre = std::max(offCentre, std::abs(centre[k] - mid) / half);
    }
    return 1.0 - std::min(offCentre, 1.0);
  }

 private:
  const kernels::CellSolver& solver_;
  bool framed_ = false;  // an affine volume cell other than a tetrahedron (FrameCoordinates)
  bool tetrahedron_ = false;  // a tetrahedron with an invertible corner map
  const double* origin_ = nullptr;
  double inverse_[3][3] = {};
};

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
    const StartScore scoreOf(solver);
    for (std::int64_t z = first[2]; z <= last[2]; ++z) {
      for (std::int64_t y = first[1]; y <= last[1]; ++y) {
        const double centre0[3] = {lo_[0] + 0.5 * stepOf[0], lo_[1] + (static_cast<double>(y) + 0.5) * stepOf[1],
                                   lo_[2] + (static_cast<double>(z) + 0.5) * stepOf[2]};
        std::int64_t firstX = first[0], lastX = last[0];
        scoreOf.NarrowRow(centre0, stepOf[0], &firstX, &lastX);
        for (std::int64_t x = firstX; x <= lastX; ++x) {
          const double centre[3] = {lo_[0] + (static_cast<double>(x) + 0.5) * stepOf[0], centre0[1], centre0[2]};
          const std::size_t index = Slot(x, y, z);
          const double s = scoreOf(centre);
          // A tetrahedron or affine cell that does not hold the centre is
          // no start for it (the neighbours' fill covers grid cells no cell
          // holds).
          if (s >= 0.0 && s > score[index]) {
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
