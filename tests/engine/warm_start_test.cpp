// The warm start of a point's search: the cell across a B-spline span
// boundary (checked against the cells' parameter intervals, found by brute
// force) and the Gauss-Newton prediction of the next point's foot (checked
// against feet known by construction).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "engine/cell_store.h"
#include "engine/warm_start.h"
#include "invmap/invmap.h"
#include "kernels/cell_map.h"
#include "tests/engine/built_cells.h"
#include "tests/support/test_geometries.h"

namespace invmap::testing {
namespace {

/// True when the numbers agree to rounding of the knots' scale.
bool Same(double a, double b) { return std::abs(a - b) <= 1e-12 * (1.0 + std::abs(a) + std::abs(b)); }

/// The cell of `cell`'s patch whose parameter interval, in every direction d,
/// is `step[d]` intervals away (-1: ends where `cell`'s starts, 0: the same,
/// +1: starts where it ends), by comparing every cell's intervals; -1 if none.
std::int64_t NeighborByIntervals(const engine::CellStore& store, std::int64_t cell, const int* step, int paramDim) {
  const engine::CellOrigin& from = store.origin(cell);
  const std::int64_t first = store.patchFirstCell(from.patch), end = store.patchFirstCell(from.patch + 1);
  std::int64_t found = -1;
  for (std::int64_t c = first; c < end; ++c) {
    const engine::CellOrigin& to = store.origin(c);
    bool adjacent = true;
    for (int d = 0; d < paramDim; ++d) {
      const double fromHi = from.paramLo[d] + from.paramScale[d], toHi = to.paramLo[d] + to.paramScale[d];
      adjacent = adjacent && (step[d] == 0  ? Same(to.paramLo[d], from.paramLo[d]) && Same(toHi, fromHi)
                              : step[d] > 0 ? Same(to.paramLo[d], fromHi)
                                            : Same(toHi, from.paramLo[d]));
    }
    if (!adjacent) continue;
    EXPECT_EQ(found, -1) << "two cells " << found << " and " << c << " fit";
    found = c;
  }
  return found;
}

/// Every cell and every step in {-1, 0, 1}^paramDim of every patch of `geometry`.
void ExpectNeighborsMatchIntervals(const Geometry& geometry) {
  const engine::CellStore store = BuildCells(geometry);
  int crossings = 0;
  for (std::int64_t cell = 0; cell < store.size(); ++cell) {
    const int paramDim = store.solver(cell).cell().shape.paramDim();
    const int combinations = static_cast<int>(std::pow(3, paramDim));
    for (int code = 0; code < combinations; ++code) {
      int step[3] = {0, 0, 0};
      for (int d = 0, rest = code; d < paramDim; ++d, rest /= 3) step[d] = rest % 3 - 1;
      const std::int64_t expected =
          store.origin(cell).sharedParameters ? NeighborByIntervals(store, cell, step, paramDim) : -1;
      ASSERT_EQ(store.SplineNeighbor(cell, step), expected)
          << "cell " << cell << " step (" << step[0] << ", " << step[1] << ", " << step[2] << ")";
      crossings += expected >= 0 && code != combinations / 2 ? 1 : 0;
    }
  }
  EXPECT_GT(crossings, 0);
}

TEST(WarmStartTest, SplineNeighborIsTheCellAcrossEachSpanBoundary) {
  // Repeated interior knots (empty spans are no cells), unclamped knots,
  // curves, surfaces and volumes, several patches.
  ExpectNeighborsMatchIntervals(WavySurfaces());
  ExpectNeighborsMatchIntervals(BSplineCurves(2));
  ExpectNeighborsMatchIntervals(BSplineCurves(3));
  ExpectNeighborsMatchIntervals(BSplineVolumes());
}

TEST(WarmStartTest, CellsOfOtherPatchesHaveNoSplineNeighbor) {
  const engine::CellStore store = BuildCells(MixedGeometry3());
  int others = 0;
  for (std::int64_t cell = 0; cell < store.size(); ++cell) {
    if (store.origin(cell).sharedParameters) continue;
    const int none[3] = {0, 0, 0}, next[3] = {1, 0, 0};
    EXPECT_EQ(store.SplineNeighbor(cell, none), -1) << "cell " << cell;
    EXPECT_EQ(store.SplineNeighbor(cell, next), -1) << "cell " << cell;
    ++others;
  }
  EXPECT_GT(others, 0);
}

/// A place on patch 0 of WavySurfaces, by its patch parameters.
struct SurfacePlace {
  std::int64_t cell = -1;
  double ref[2] = {0, 0};
  kernels::MapJet jet;  ///< To second order.
  double normal[3] = {0, 0, 0};
};

SurfacePlace PlaceAt(const engine::CellStore& store, const double* u) {
  SurfacePlace place;
  for (std::int64_t c = store.patchFirstCell(0); c < store.patchFirstCell(1); ++c) {
    const engine::CellOrigin& o = store.origin(c);
    bool holds = true;
    for (int d = 0; d < 2; ++d) holds = holds && u[d] >= o.paramLo[d] && u[d] <= o.paramLo[d] + o.paramScale[d];
    if (!holds) continue;
    place.cell = c;
    for (int d = 0; d < 2; ++d) place.ref[d] = (u[d] - o.paramLo[d]) / o.paramScale[d];
    break;
  }
  if (place.cell < 0) return place;
  kernels::EvaluateMap(store.solver(place.cell).cell(), place.ref, kernels::JetOrder::Second, &place.jet);
  const double(*j)[3] = place.jet.d1;
  const double n[3] = {j[1][0] * j[2][1] - j[2][0] * j[1][1], j[2][0] * j[0][1] - j[0][0] * j[2][1],
                       j[0][0] * j[1][1] - j[1][0] * j[0][1]};
  const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int k = 0; k < 3; ++k) place.normal[k] = n[k] / length;
  return place;
}

/// The warm start of the query point `point` answered at `place`: its
/// Jacobian, and with `hessian` the Hessian of half the squared distance
/// (J^T J + sum_k r_k d2x_k, the definition) from the place's jet.
engine::WarmStart WarmAt(const SurfacePlace& place, const double* point, bool hessian) {
  engine::WarmStart warm;
  warm.cell = place.cell;
  std::copy(place.ref, place.ref + 2, warm.ref);
  warm.model.known = true;
  std::fill(&warm.model.jacobian[0][0], &warm.model.jacobian[0][0] + 9, 0.0);
  std::fill(&warm.model.hessian[0][0], &warm.model.hessian[0][0] + 9, 0.0);
  for (int k = 0; k < 3; ++k) {
    warm.point[k] = point[k];
    warm.closest[k] = place.jet.x[k];
    for (int i = 0; i < 2; ++i) warm.model.jacobian[k][i] = place.jet.d1[k][i];
  }
  for (int i = 0; hessian && i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      for (int k = 0; k < 3; ++k) {
        warm.model.hessian[i][j] +=
            place.jet.d1[k][i] * place.jet.d1[k][j] + (place.jet.x[k] - point[k]) * place.jet.d2[k][i][j];
      }
    }
  }
  return warm;
}

/// The patch parameters of reference point `ref` of `cell`.
void PatchParameters(const engine::CellStore& store, std::int64_t cell, const double* ref, double* u) {
  const engine::CellOrigin& o = store.origin(cell);
  for (int d = 0; d < 2; ++d) u[d] = o.paramLo[d] + o.paramScale[d] * ref[d];
}

/// Points answered at u (at a height h along the normal, so their foot is
/// u), then the next at a height along the normal at u + delta (so its foot
/// is u + delta): the prediction from the first's answer must land much
/// nearer u + delta than u, in the cell that holds it. Returns the ratios
/// of the distance after to the distance before, sorted.
std::vector<double> PredictionRatios(double height, bool hessian, int* inCell, int* crossed) {
  const engine::CellStore store = BuildCells(WavySurfaces());
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> unit(0.0, 1.0), signed01(-1.0, 1.0);
  std::vector<double> ratios;
  *inCell = *crossed = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const double u[2] = {0.05 + 0.9 * unit(rng), 0.05 + 0.9 * unit(rng)};
    const SurfacePlace from = PlaceAt(store, u);
    const double* span = store.origin(from.cell).paramScale;
    const double target[2] = {u[0] + 0.5 * span[0] * signed01(rng), u[1] + 0.5 * span[1] * signed01(rng)};
    const SurfacePlace to = PlaceAt(store, target);
    const double h = height * signed01(rng), hNext = height * signed01(rng);
    double previous[3], p[3];
    for (int k = 0; k < 3; ++k) {
      previous[k] = from.jet.x[k] + h * from.normal[k];
      p[k] = to.jet.x[k] + hNext * to.normal[k];
    }
    std::int64_t cell;
    double ref[3];
    engine::PredictStart(store, WarmAt(from, previous, hessian), p, &cell, ref);
    double landed[2];
    PatchParameters(store, cell, ref, landed);
    const double before = std::hypot(u[0] - target[0], u[1] - target[1]);
    const double after = std::hypot(landed[0] - target[0], landed[1] - target[1]);
    ratios.push_back(after / before);
    // The start lies in the cell returned, unless the step crossed more
    // than one span in a direction (narrow spans of the random knots).
    *inCell += PlaceAt(store, landed).cell == cell ? 1 : 0;
    *crossed += cell != from.cell ? 1 : 0;
  }
  std::sort(ratios.begin(), ratios.end());
  return ratios;
}

TEST(WarmStartTest, GaussNewtonStepPredictsTheNextFootAcrossSpans) {
  // Without a Hessian, near the surface (h up to 1e-4, where J^T J is
  // nearly the Hessian).
  int inCell, crossed;
  const std::vector<double> ratios = PredictionRatios(1e-4, false, &inCell, &crossed);
  // Never farther than the answer itself (a repeated knot bends the
  // parametrization; the step is only first order), usually an order of
  // magnitude nearer (measured: median 0.04, 95th percentile 0.18).
  EXPECT_LT(ratios.back(), 1.0);
  EXPECT_LT(ratios[ratios.size() / 2], 0.1);
  EXPECT_LT(ratios[ratios.size() * 95 / 100], 0.3);
  EXPECT_GT(inCell, 1900);
  EXPECT_GT(crossed, 200);
}

TEST(WarmStartTest, NewtonStepPredictsTheNextFootOfPointsOffTheSurface) {
  // Heights up to 0.05, beyond a tenth of the wavy surface's radii of
  // curvature: the Hessian's curvature term matters there.
  int inCell, crossed;
  const std::vector<double> newton = PredictionRatios(0.05, true, &inCell, &crossed);
  // Measured: median 0.065, 90th percentile 0.31 (Gauss-Newton: 0.43).
  EXPECT_LT(newton[newton.size() / 2], 0.1);
  EXPECT_LT(newton[newton.size() * 9 / 10], 0.4);
  EXPECT_GT(inCell, 1800);
  EXPECT_GT(crossed, 200);
  // Gauss-Newton misses that term.
  const std::vector<double> gaussNewton = PredictionRatios(0.05, false, &inCell, &crossed);
  EXPECT_LT(newton[newton.size() * 9 / 10], gaussNewton[gaussNewton.size() * 9 / 10]);
}

TEST(WarmStartTest, StartsAtThePreviousAnswerWithoutAModelOrForARepeatedPoint) {
  const engine::CellStore store = BuildCells(WavySurfaces());
  const double u[2] = {0.4, 0.3};
  const SurfacePlace from = PlaceAt(store, u);
  double previous[3];
  for (int k = 0; k < 3; ++k) previous[k] = from.jet.x[k] + 0.01 * from.normal[k];
  engine::WarmStart warm = WarmAt(from, previous, true);
  std::int64_t cell;
  double ref[3];
  // The same point again: the previous answer exactly.
  engine::PredictStart(store, warm, previous, &cell, ref);
  EXPECT_EQ(cell, from.cell);
  EXPECT_EQ(ref[0], from.ref[0]);
  EXPECT_EQ(ref[1], from.ref[1]);
  // Elsewhere, but no model: the previous answer.
  const double elsewhere[3] = {0.9, 0.1, 0.0};
  warm.model.known = false;
  engine::PredictStart(store, warm, elsewhere, &cell, ref);
  EXPECT_EQ(cell, from.cell);
  EXPECT_EQ(ref[0], from.ref[0]);
  EXPECT_EQ(ref[1], from.ref[1]);
  // No previous answer: no cell.
  engine::PredictStart(store, engine::WarmStart(), elsewhere, &cell, ref);
  EXPECT_EQ(cell, -1);
}

TEST(WarmStartTest, AStepPastThePatchEdgeIsHeldOnTheEdge) {
  // Points beyond the patch's edge u = 0, off a curved edge: the previous
  // one's foot is the edge point at v, the next one's at v + delta (a
  // point displaced from the edge curve C(v) away from the patch, normal to
  // C). The start stays on the edge and slides toward v + delta, into the
  // next span when that holds it.
  const engine::CellStore store = BuildCells(WavySurfaces());
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> unit(0.0, 1.0), signed01(-1.0, 1.0);
  // Away from the patch, normal to the edge curve, at distance d: x +
  // d * (-(S_u - (S_u . t) t) / |...|), t the unit tangent S_v / |S_v|.
  auto beyond = [](const SurfacePlace& place, double d, double* p) {
    const double(*j)[3] = place.jet.d1;
    const double tv = std::hypot(j[0][1], j[1][1], j[2][1]);
    double dot = 0.0;
    for (int k = 0; k < 3; ++k) dot += j[k][0] * j[k][1] / tv;
    double w[3];
    for (int k = 0; k < 3; ++k) w[k] = -(j[k][0] - dot * j[k][1] / tv);
    const double length = std::hypot(w[0], w[1], w[2]);
    for (int k = 0; k < 3; ++k) p[k] = place.jet.x[k] + d * w[k] / length;
  };
  int improved = 0, moved = 0;
  const int trials = 500;
  for (int trial = 0; trial < trials; ++trial) {
    const double u[2] = {0.0, 0.1 + 0.8 * unit(rng)};
    const SurfacePlace from = PlaceAt(store, u);
    const double target[2] = {0.0, u[1] + 0.5 * store.origin(from.cell).paramScale[1] * signed01(rng)};
    const SurfacePlace to = PlaceAt(store, target);
    const double d = 0.01 + 0.04 * unit(rng);
    double previous[3], p[3];
    beyond(from, d, previous);
    beyond(to, d, p);
    std::int64_t cell;
    double ref[3];
    engine::PredictStart(store, WarmAt(from, previous, true), p, &cell, ref);
    ASSERT_EQ(ref[0], 0.0) << "trial " << trial;
    double landed[2];
    PatchParameters(store, cell, ref, landed);
    improved += std::abs(landed[1] - target[1]) < 0.5 * std::abs(u[1] - target[1]) ? 1 : 0;
    moved += cell != from.cell ? 1 : 0;
  }
  // Measured: 481 of 500 (the rest where the edge curves almost as much as
  // 1 / d, so the foot is barely stable along it).
  EXPECT_GT(improved, trials * 9 / 10);
  EXPECT_GT(moved, trials / 10);
}

/// The least value of a convex quadratic with some parameters held: at that
/// point the gradient along the free ones vanishes (checked directly).
TEST(WarmStartTest, SolveFreeFindsTheLeastValueWithHeldParameters) {
  const double model[3][3] = {{4.0, 1.0, 0.5}, {1.0, 3.0, -0.7}, {0.5, -0.7, 2.0}};
  const double rhs[3] = {0.3, -0.2, 0.1};
  for (int paramDim = 1; paramDim <= 3; ++paramDim) {
    for (int mask = 0; mask < (1 << paramDim); ++mask) {
      bool held[3] = {false, false, false};
      double step[3] = {0, 0, 0};
      for (int i = 0; i < paramDim; ++i) {
        held[i] = (mask >> i) & 1;
        if (held[i]) step[i] = 0.25 * (i + 1);
      }
      const double heldStep[3] = {step[0], step[1], step[2]};
      ASSERT_TRUE(engine::SolveFree(model, rhs, paramDim, held, step));
      for (int i = 0; i < paramDim; ++i) {
        if (held[i]) {
          EXPECT_EQ(step[i], heldStep[i]);
          continue;
        }
        double residual = -rhs[i];
        for (int j = 0; j < paramDim; ++j) residual += model[i][j] * step[j];
        EXPECT_NEAR(residual, 0.0, 1e-14) << "paramDim " << paramDim << " mask " << mask << " row " << i;
      }
    }
  }
  // A free block that is not positive definite has no least value.
  const double saddle[3][3] = {{1.0, 0.0, 0.0}, {0.0, -1.0, 0.0}, {0.0, 0.0, 1.0}};
  const bool none[3] = {false, false, false};
  double step[3] = {0, 0, 0};
  EXPECT_FALSE(engine::SolveFree(saddle, rhs, 2, none, step));
  const bool secondHeld[3] = {false, true, false};
  EXPECT_TRUE(engine::SolveFree(saddle, rhs, 2, secondHeld, step));
}

}  // namespace
}  // namespace invmap::testing
