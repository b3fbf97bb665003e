#include "engine/affine_regions.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/cell_map.h"
#include "kernels/tolerances.h"

namespace invmap::engine {
namespace {

/// A cell's affine map in patch parameters.
struct AffineMap {
  double A[3][3] = {};
  double b[3] = {0, 0, 0};
};

/// The cells of one spline grid: their solvers and origins, built.
struct GridCells {
  const std::vector<kernels::CellSolver>& solvers;
  const std::vector<CellOrigin>& origins;
  int dim;
};

AffineMap CellMap(const GridCells& cells, std::int64_t cell, int paramDim, int dim) {
  const kernels::CellView& view = cells.solvers[cell].cell();
  const CellOrigin& origin = cells.origins[cell];
  const double zero[3] = {0, 0, 0};
  kernels::MapJet at0;
  kernels::EvaluateMap(view, zero, kernels::JetOrder::Value, &at0);
  AffineMap map;
  for (int d = 0; d < paramDim; ++d) {
    double unit[3] = {0, 0, 0};
    unit[d] = 1;
    kernels::MapJet atUnit;
    kernels::EvaluateMap(view, unit, kernels::JetOrder::Value, &atUnit);
    for (int k = 0; k < dim; ++k) map.A[k][d] = (atUnit.x[k] - at0.x[k]) / origin.paramScale[d];
  }
  for (int k = 0; k < dim; ++k) {
    map.b[k] = at0.x[k];
    for (int d = 0; d < paramDim; ++d) map.b[k] -= map.A[k][d] * origin.paramLo[d];
  }
  return map;
}

/// True when `map` reproduces the cell's own map at every corner of the cell
/// to `tolerance`.
bool SameMap(const GridCells& cells, std::int64_t cell, const AffineMap& map, int paramDim, int dim,
             double tolerance) {
  const kernels::CellView& view = cells.solvers[cell].cell();
  const CellOrigin& origin = cells.origins[cell];
  for (int corner = 0; corner < (1 << paramDim); ++corner) {
    double ref[3] = {0, 0, 0}, u[3] = {0, 0, 0};
    for (int d = 0; d < paramDim; ++d) {
      ref[d] = (corner >> d) & 1;
      u[d] = origin.paramLo[d] + origin.paramScale[d] * ref[d];
    }
    kernels::MapJet jet;
    kernels::EvaluateMap(view, ref, kernels::JetOrder::Value, &jet);
    double error2 = 0;
    for (int k = 0; k < dim; ++k) {
      double x = map.b[k];
      for (int d = 0; d < paramDim; ++d) x += map.A[k][d] * u[d];
      error2 += (x - jet.x[k]) * (x - jet.x[k]);
    }
    if (!(error2 <= tolerance * tolerance)) return false;
  }
  return true;
}

/// Gram matrix G = A^T A of the map's columns.
void Gram(const AffineRegion& r, double G[3][3]) {
  for (int i = 0; i < r.paramDim; ++i)
    for (int j = 0; j < r.paramDim; ++j) {
      G[i][j] = 0;
      for (int k = 0; k < r.ambientDim; ++k) G[i][j] += r.A[k][i] * r.A[k][j];
    }
}

/// A region is solved by normal equations; it must not be nearly flat in
/// some direction (its cells would be degenerate), or the face solves would
/// lose accuracy: the Gram matrix scaled to unit diagonal must be well
/// conditioned.
bool WellConditioned(const AffineRegion& r) {
  double G[3][3];
  Gram(r, G);
  double scaled[3][3];
  for (int i = 0; i < r.paramDim; ++i) {
    if (!(G[i][i] > 0)) return false;
    for (int j = 0; j < r.paramDim; ++j) scaled[i][j] = G[i][j] / std::sqrt(G[i][i] * G[j][j]);
  }
  double det = 1;
  if (r.paramDim == 2) det = 1 - scaled[0][1] * scaled[0][1];
  if (r.paramDim == 3) {
    det = scaled[0][0] * (scaled[1][1] * scaled[2][2] - scaled[1][2] * scaled[2][1]) -
          scaled[0][1] * (scaled[1][0] * scaled[2][2] - scaled[1][2] * scaled[2][0]) +
          scaled[0][2] * (scaled[1][0] * scaled[2][1] - scaled[1][1] * scaled[2][0]);
  }
  return det > kernels::kRegionConditioning;
}

/// Solves the m x m symmetric positive definite system M x = r (m <= 3) by
/// Cholesky.
void SolveSpd(double M[3][3], double* r, int m) {
  double L[3][3] = {};
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j <= i; ++j) {
      double sum = M[i][j];
      for (int k = 0; k < j; ++k) sum -= L[i][k] * L[j][k];
      L[i][j] = i == j ? std::sqrt(sum) : sum / L[j][j];
    }
  }
  for (int i = 0; i < m; ++i) {
    for (int k = 0; k < i; ++k) r[i] -= L[i][k] * r[k];
    r[i] /= L[i][i];
  }
  for (int i = m - 1; i >= 0; --i) {
    for (int k = i + 1; k < m; ++k) r[i] -= L[k][i] * r[k];
    r[i] /= L[i][i];
  }
}

double Distance2(const AffineRegion& r, const double* u, const double* p, double* x) {
  double d2 = 0;
  for (int k = 0; k < r.ambientDim; ++k) {
    x[k] = r.b[k];
    for (int d = 0; d < r.paramDim; ++d) x[k] += r.A[k][d] * u[d];
    d2 += (x[k] - p[k]) * (x[k] - p[k]);
  }
  return d2;
}

/// The minimizer on the face where direction d is free (state 0), at lo
/// (state 1) or at hi (state 2); false when it leaves the face.
bool SolveFace(const AffineRegion& r, const double G[3][3], const int* state, const double* p, double* u) {
  int freeDirs[3], m = 0;
  for (int d = 0; d < r.paramDim; ++d) {
    if (state[d] == 0) {
      freeDirs[m++] = d;
    } else {
      u[d] = state[d] == 1 ? r.lo[d] : r.hi[d];
    }
  }
  if (m == 0) return true;
  // Normal equations on the free directions: G_FF u_F = A_F^T (p - b - A_fixed u_fixed).
  double residual[3];
  for (int k = 0; k < r.ambientDim; ++k) {
    residual[k] = p[k] - r.b[k];
    for (int d = 0; d < r.paramDim; ++d)
      if (state[d] != 0) residual[k] -= r.A[k][d] * u[d];
  }
  double M[3][3], rhs[3];
  for (int i = 0; i < m; ++i) {
    rhs[i] = 0;
    for (int k = 0; k < r.ambientDim; ++k) rhs[i] += r.A[k][freeDirs[i]] * residual[k];
    for (int j = 0; j < m; ++j) M[i][j] = G[freeDirs[i]][freeDirs[j]];
  }
  SolveSpd(M, rhs, m);
  for (int i = 0; i < m; ++i) {
    const int d = freeDirs[i];
    // Rounding may put an on-face minimizer a hair outside: clamp within a
    // relative slack; beyond it the minimizer is on another face.
    const double slack = kernels::kRegionFaceSlack * (r.hi[d] - r.lo[d]);
    if (!(rhs[i] >= r.lo[d] - slack && rhs[i] <= r.hi[d] + slack)) return false;
    u[d] = std::clamp(rhs[i], r.lo[d], r.hi[d]);
  }
  return true;
}

/// The regions of one grid: greedy maximal boxes of at least 2 affine cells
/// whose maps agree to `tolerance` (a length) at every cell corner, laid
/// out u fastest; appended to `regions`.
void FindGridRegions(const GridCells& cells, std::int64_t firstCell, const int spans[3], int paramDim,
                     double tolerance, std::vector<AffineRegion>* regions) {
  const int dim = cells.dim;
  const std::int64_t nx = spans[0], ny = spans[1], nz = spans[2];
  auto index = [&](std::int64_t i, std::int64_t j, std::int64_t k) { return firstCell + i + nx * (j + ny * k); };
  std::vector<char> assigned(static_cast<std::size_t>(nx * ny * nz), 0);
  auto fits = [&](std::int64_t i, std::int64_t j, std::int64_t k, const AffineMap& map) {
    const std::int64_t c = index(i, j, k);
    return !assigned[c - firstCell] && cells.solvers[c].isAffine() && SameMap(cells, c, map, paramDim, dim, tolerance);
  };
  for (std::int64_t k = 0; k < nz; ++k) {
    for (std::int64_t j = 0; j < ny; ++j) {
      for (std::int64_t i = 0; i < nx; ++i) {
        const std::int64_t start = index(i, j, k);
        if (assigned[start - firstCell] || !cells.solvers[start].isAffine()) continue;
        const AffineMap map = CellMap(cells, start, paramDim, dim);
        std::int64_t i1 = i, j1 = j, k1 = k;
        while (i1 + 1 < nx && fits(i1 + 1, j, k, map)) ++i1;
        auto rowFits = [&](std::int64_t jj, std::int64_t kk) {
          for (std::int64_t ii = i; ii <= i1; ++ii)
            if (!fits(ii, jj, kk, map)) return false;
          return true;
        };
        while (j1 + 1 < ny && rowFits(j1 + 1, k)) ++j1;
        auto layerFits = [&](std::int64_t kk) {
          for (std::int64_t jj = j; jj <= j1; ++jj)
            if (!rowFits(jj, kk)) return false;
          return true;
        };
        while (k1 + 1 < nz && layerFits(k1 + 1)) ++k1;
        if ((i1 - i + 1) * (j1 - j + 1) * (k1 - k + 1) < 2) continue;

        AffineRegion region;
        region.paramDim = paramDim;
        region.ambientDim = dim;
        std::copy(&map.A[0][0], &map.A[0][0] + 9, &region.A[0][0]);
        std::copy(map.b, map.b + 3, region.b);
        region.firstCell = start;
        const std::int64_t from[3] = {i, j, k}, to[3] = {i1, j1, k1}, stride[3] = {1, nx, nx * ny};
        for (int d = 0; d < paramDim; ++d) {
          region.cellStride[d] = stride[d];
          for (std::int64_t t = from[d]; t <= to[d]; ++t)
            region.breaks[d].push_back(cells.origins[start + (t - from[d]) * stride[d]].paramLo[d]);
          const CellOrigin& last = cells.origins[start + (to[d] - from[d]) * stride[d]];
          region.breaks[d].push_back(last.paramLo[d] + last.paramScale[d]);
          region.lo[d] = region.breaks[d].front();
          region.hi[d] = region.breaks[d].back();
        }
        if (!WellConditioned(region)) continue;
        for (int a = 0; a < 3; ++a) {
          region.boxLo[a] = std::numeric_limits<double>::infinity();
          region.boxHi[a] = -std::numeric_limits<double>::infinity();
        }
        for (std::int64_t kk = k; kk <= k1; ++kk)
          for (std::int64_t jj = j; jj <= j1; ++jj)
            for (std::int64_t ii = i; ii <= i1; ++ii) {
              const std::int64_t c = index(ii, jj, kk);
              assigned[c - firstCell] = 1;
              for (int a = 0; a < 3; ++a) {
                region.boxLo[a] = std::min(region.boxLo[a], cells.solvers[c].boxLo()[a]);
                region.boxHi[a] = std::max(region.boxHi[a], cells.solvers[c].boxHi()[a]);
              }
            }
        regions->push_back(std::move(region));
      }
    }
  }
}

}  // namespace

std::int64_t AffineRegion::numCells() const {
  std::int64_t n = 1;
  for (int d = 0; d < paramDim; ++d) n *= static_cast<std::int64_t>(breaks[d].size()) - 1;
  return n;
}

RegionSolution SolveAffineRegion(const AffineRegion& region, const double* point) {
  double G[3][3];
  Gram(region, G);
  RegionSolution best;
  double best2 = std::numeric_limits<double>::infinity();
  int faces = 1;
  for (int d = 0; d < region.paramDim; ++d) faces *= 3;
  // Face 0 is the interior (every direction free): when its minimizer is in
  // the box it is the answer.
  for (int face = 0; face < faces; ++face) {
    int state[3] = {0, 0, 0};
    for (int d = 0, f = face; d < region.paramDim; ++d, f /= 3) state[d] = f % 3;
    double u[3] = {0, 0, 0}, x[3] = {0, 0, 0};
    if (!SolveFace(region, G, state, point, u)) continue;
    const double d2 = Distance2(region, u, point, x);
    if (d2 < best2) {
      best2 = d2;
      std::copy(u, u + 3, best.u);
      std::copy(x, x + 3, best.closest);
    }
    if (face == 0) break;
  }
  best.distance = std::sqrt(best2);
  best.cell = region.firstCell;
  for (int d = 0; d < region.paramDim; ++d) {
    const std::vector<double>& breaks = region.breaks[d];
    const int spans = static_cast<int>(breaks.size()) - 1;
    const int span = std::clamp(
        static_cast<int>(std::upper_bound(breaks.begin() + 1, breaks.end() - 1, best.u[d]) - breaks.begin()) - 1, 0,
        spans - 1);
    best.cell += span * region.cellStride[d];
    best.ref[d] = std::clamp((best.u[d] - breaks[span]) / (breaks[span + 1] - breaks[span]), 0.0, 1.0);
  }
  return best;
}

std::vector<AffineRegion> FindAffineRegions(const BezierNets& nets, const std::vector<kernels::CellSolver>& solvers) {
  std::vector<AffineRegion> regions;
  if (nets.splineGrids.empty()) return regions;
  const int dim = nets.dimension;
  const GridCells cells{solvers, nets.origins, dim};
  double coordinateMagnitude = 0.0;
  for (double x : nets.points) coordinateMagnitude = std::max(coordinateMagnitude, std::fabs(x));
  for (const SplineGrid& grid : nets.splineGrids) {
    const std::int64_t count = static_cast<std::int64_t>(grid.spans[0]) * grid.spans[1] * grid.spans[2];
    double diagonal2 = 0.0;
    for (int k = 0; k < dim; ++k) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (std::int64_t c = grid.firstCell; c < grid.firstCell + count; ++c) {
        lo = std::min(lo, solvers[c].boxLo()[k]);
        hi = std::max(hi, solvers[c].boxHi()[k]);
      }
      diagonal2 += (hi - lo) * (hi - lo);
    }
    const double tolerance =
        kernels::kAffineRegionTolerance * std::sqrt(diagonal2) + kernels::kCoordinateRounding * coordinateMagnitude;
    FindGridRegions(cells, grid.firstCell, grid.spans.data(), grid.paramDim, tolerance, &regions);
  }
  return regions;
}

}  // namespace invmap::engine
