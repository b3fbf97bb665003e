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
  engine::CellStore store;
  ASSERT_EQ(store.Build(geometry, 1), "");
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
  engine::CellStore store;
  ASSERT_EQ(store.Build(MixedGeometry3(), 1), "");
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
  kernels::MapJet jet;
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
  kernels::EvaluateMap(store.solver(place.cell).cell(), place.ref, kernels::JetOrder::First, &place.jet);
  const double(*j)[3] = place.jet.d1;
  const double n[3] = {j[1][0] * j[2][1] - j[2][0] * j[1][1], j[2][0] * j[0][1] - j[0][0] * j[2][1],
                       j[0][0] * j[1][1] - j[1][0] * j[0][1]};
  const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int k = 0; k < 3; ++k) place.normal[k] = n[k] / length;
  return place;
}

/// The patch parameters of reference point `ref` of `cell`.
void PatchParameters(const engine::CellStore& store, std::int64_t cell, const double* ref, double* u) {
  const engine::CellOrigin& o = store.origin(cell);
  for (int d = 0; d < 2; ++d) u[d] = o.paramLo[d] + o.paramScale[d] * ref[d];
}

TEST(WarmStartTest, GaussNewtonStepPredictsTheNextFootAcrossSpans) {
  // A point answered at u, then the next at a small height along the
  // normal at u + delta (so its foot is u + delta): the prediction from the
  // first's answer must land much nearer u + delta than u, in the cell that
  // holds it.
  engine::CellStore store;
  ASSERT_EQ(store.Build(WavySurfaces(), 1), "");
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> unit(0.0, 1.0), signed01(-1.0, 1.0);
  int inCell = 0, crossed = 0;
  std::vector<double> ratios;
  for (int trial = 0; trial < 2000; ++trial) {
    const double u[2] = {0.05 + 0.9 * unit(rng), 0.05 + 0.9 * unit(rng)};
    const SurfacePlace from = PlaceAt(store, u);
    ASSERT_GE(from.cell, 0);
    const double* span = store.origin(from.cell).paramScale;
    const double target[2] = {u[0] + 0.5 * span[0] * signed01(rng), u[1] + 0.5 * span[1] * signed01(rng)};
    const SurfacePlace to = PlaceAt(store, target);
    ASSERT_GE(to.cell, 0);
    const double h = 1e-4 * signed01(rng), hNext = 1e-4 * signed01(rng);

    engine::WarmStart warm;
    warm.cell = from.cell;
    std::copy(from.ref, from.ref + 2, warm.ref);
    for (int k = 0; k < 3; ++k) {
      warm.point[k] = from.jet.x[k] + h * from.normal[k];
      warm.closest[k] = from.jet.x[k];
      for (int i = 0; i < 2; ++i) warm.jacobian[k][i] = from.jet.d1[k][i];
    }
    double p[3];
    for (int k = 0; k < 3; ++k) p[k] = to.jet.x[k] + hNext * to.normal[k];

    std::int64_t cell;
    double ref[3];
    engine::PredictStart(store, warm, p, &cell, ref);
    double landed[2];
    PatchParameters(store, cell, ref, landed);
    const double before = std::hypot(u[0] - target[0], u[1] - target[1]);
    const double after = std::hypot(landed[0] - target[0], landed[1] - target[1]);
    // Never farther than the answer itself (a repeated knot bends the
    // parametrization; the step is only first order).
    ASSERT_LT(after, before) << "trial " << trial;
    ratios.push_back(after / before);
    // The start lies in the cell returned, unless the step crossed more
    // than one span in a direction (narrow spans of the random knots).
    inCell += PlaceAt(store, landed).cell == cell ? 1 : 0;
    crossed += cell != from.cell ? 1 : 0;
  }
  // Usually an order of magnitude nearer (measured: median 0.04, 95th
  // percentile 0.18 of the distance before the step).
  std::sort(ratios.begin(), ratios.end());
  EXPECT_LT(ratios[ratios.size() / 2], 0.1);
  EXPECT_LT(ratios[ratios.size() * 95 / 100], 0.3);
  EXPECT_GT(inCell, 1900);
  EXPECT_GT(crossed, 200);
}

TEST(WarmStartTest, StartsAtThePreviousAnswerWithoutAJacobianOrForARepeatedPoint) {
  engine::CellStore store;
  ASSERT_EQ(store.Build(WavySurfaces(), 1), "");
  const double u[2] = {0.4, 0.3};
  const SurfacePlace from = PlaceAt(store, u);
  engine::WarmStart warm;
  warm.cell = from.cell;
  std::copy(from.ref, from.ref + 2, warm.ref);
  for (int k = 0; k < 3; ++k) {
    warm.point[k] = from.jet.x[k] + 0.01 * from.normal[k];
    warm.closest[k] = from.jet.x[k];
  }
  const double elsewhere[3] = {0.9, 0.1, 0.0};
  std::int64_t cell;
  double ref[3];
  // No Jacobian: the previous answer.
  engine::PredictStart(store, warm, elsewhere, &cell, ref);
  EXPECT_EQ(cell, from.cell);
  EXPECT_EQ(ref[0], from.ref[0]);
  EXPECT_EQ(ref[1], from.ref[1]);
  // The same point again, with a Jacobian: the previous answer exactly.
  for (int k = 0; k < 3; ++k) {
    for (int i = 0; i < 2; ++i) warm.jacobian[k][i] = from.jet.d1[k][i];
  }
  const double again[3] = {warm.point[0], warm.point[1], warm.point[2]};
  engine::PredictStart(store, warm, again, &cell, ref);
  EXPECT_EQ(cell, from.cell);
  EXPECT_EQ(ref[0], from.ref[0]);
  EXPECT_EQ(ref[1], from.ref[1]);
  // No previous answer: no cell.
  engine::PredictStart(store, engine::WarmStart(), again, &cell, ref);
  EXPECT_EQ(cell, -1);
}

TEST(WarmStartTest, AStepOffThePatchStaysInTheEdgeCell) {
  engine::CellStore store;
  ASSERT_EQ(store.Build(WavySurfaces(), 1), "");
  // The corner cell at u = (0, 0); the next point lies beyond the patch's
  // u = 0 edge: the start leaves the unit box there (the solve clamps it).
  const double u[2] = {1e-3, 0.5};
  const SurfacePlace from = PlaceAt(store, u);
  engine::WarmStart warm;
  warm.cell = from.cell;
  std::copy(from.ref, from.ref + 2, warm.ref);
  double p[3];
  for (int k = 0; k < 3; ++k) {
    warm.point[k] = warm.closest[k] = from.jet.x[k];
    for (int i = 0; i < 2; ++i) warm.jacobian[k][i] = from.jet.d1[k][i];
    p[k] =
        from.jet.x[k] - 0.05 * from.jet.d1[k][0] / std::hypot(from.jet.d1[0][0], from.jet.d1[1][0], from.jet.d1[2][0]);
  }
  std::int64_t cell;
  double ref[3];
  engine::PredictStart(store, warm, p, &cell, ref);
  EXPECT_EQ(cell, from.cell);
  EXPECT_LT(ref[0], 0.0);
}

}  // namespace
}  // namespace invmap::testing
