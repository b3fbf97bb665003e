// The local solve (kernels/local_solver.h) against the brute-force
// reference. Started on a face of a cell whose closest point is inside, it
// must leave the face (release the constraint) and stop at a KKT point, the
// interior minimum; a solve that stops on the face is a wrong start for the
// cell search's certificate, which only trusts KKT points. Started in the
// basin of the closest point of a curve or surface (the interior fast path),
// it must reach that point, inside or on the boundary.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "kernels/kkt_point.h"
#include "kernels/local_solver.h"
#include "tests/support/reference_cell.h"

namespace {

using invmap::kernels::CellType;
using invmap::testing::RefClosest;
using invmap::kernels::LocalSolve;
using invmap::kernels::LocalSolveOptions;
using invmap::testing::AffineCell;
using invmap::testing::BruteForceReference;
using invmap::testing::RandomCurvedCell;
using invmap::testing::RefCell;
using invmap::testing::RefEvaluateJet;
using invmap::testing::RefJet;

/// A query near the cell at reference point `u`: the point itself for a
/// volume, a small step off the surface along its normal for a surface.
void QueryNear(const RefCell& cell, const double* u, double offset, double* point) {
  RefJet jet;
  RefEvaluateJet(cell, u, 1, &jet);
  for (int k = 0; k < 3; ++k) point[k] = jet.x[k];
  if (cell.paramDim() == 3) return;
  const double n[3] = {jet.d1[1][0] * jet.d1[2][1] - jet.d1[2][0] * jet.d1[1][1],
                       jet.d1[2][0] * jet.d1[0][1] - jet.d1[0][0] * jet.d1[2][1],
                       jet.d1[0][0] * jet.d1[1][1] - jet.d1[1][0] * jet.d1[0][1]};
  const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int k = 0; k < 3; ++k) point[k] += offset * n[k] / length;
}

TEST(LocalSolve, StartOnAFaceReachesTheInteriorMinimum) {
  std::mt19937_64 rng(20261124);
  std::uniform_real_distribution<double> inner(0.3, 0.7);
  int checked = 0, matched = 0;
  for (int trial = 0; trial < 120; ++trial) {
    const CellType type = trial % 2 == 0 ? CellType::Quad : CellType::Hex;
    const RefCell cell = RandomCurvedCell(type, 2 + trial % 3 / 2, trial % 4 == 3, 3, rng);
    const int pd = cell.paramDim();
    double u[3] = {0, 0, 0};
    for (int i = 0; i < pd; ++i) u[i] = inner(rng);
    double point[3];
    QueryNear(cell, u, 0.01 * cell.size(), point);
    BruteForceReference reference(cell);
    const auto expected = reference.Closest(point);
    bool interior = true;
    for (int i = 0; i < pd; ++i) interior = interior && expected.ref[i] > 0.05 && expected.ref[i] < 0.95;
    if (!interior) continue;
    // The start: the answer's parameters with one of them moved onto a face.
    double start[3] = {expected.ref[0], expected.ref[1], expected.ref[2]};
    start[trial % pd] = trial % 3 == 0 ? 1.0 : 0.0;
    LocalSolveOptions options;
    options.size = cell.size();
    options.checkKkt = true;
    const auto result = LocalSolve(cell.view(), point, start, options);
    ++checked;
    SCOPED_TRACE(::testing::Message() << "trial " << trial << "\n" << invmap::testing::Describe(cell));
    EXPECT_TRUE(result.converged);
    EXPECT_TRUE(result.kkt) << "stopped at a point that is not a KKT point";
    if (!result.onBoundary && std::abs(std::sqrt(result.squaredDistance) - expected.distance) <= 1e-9 * cell.size()) {
      ++matched;
    }
  }
  EXPECT_GT(checked, 60);
  // A local solve may end in another basin now and then; from the basin's
  // own parameters with one moved to a face, it rarely does.
  EXPECT_GT(matched, checked * 9 / 10);
}

TEST(LocalSolve, CurvesAndSurfacesReachTheClosestPointOfTheirBasin) {
  // Lines in the plane and in space, quads in space (the interior fast
  // path's cells), degrees 1 to 4, every third rational; points near the
  // cell and up to 40% of its size away, in any direction, so that some
  // closest points lie on the boundary (the fast path hands over there).
  struct Kind {
    CellType type;
    int ambientDim;
  };
  const Kind kinds[] = {{CellType::Quad, 3}, {CellType::Line, 2}, {CellType::Line, 3}};
  std::mt19937_64 rng(424242);
  std::uniform_real_distribution<double> unit(0.0, 1.0), symmetric(-1.0, 1.0);
  int checked = 0, matched = 0, onBoundary = 0, inside = 0;
  for (int trial = 0; trial < 240; ++trial) {
    const Kind kind = kinds[trial % 3];
    const RefCell cell = RandomCurvedCell(kind.type, 1 + trial / 3 % 4, trial % 3 == 0, kind.ambientDim, rng);
    const int pd = cell.paramDim();
    const double u[2] = {unit(rng), unit(rng)};
    RefJet jet;
    RefEvaluateJet(cell, u, 0, &jet);
    const double offset = (trial % 2 == 0 ? 0.02 : 0.4) * cell.size();
    double point[3] = {0, 0, 0}, direction[3] = {0, 0, 0}, length2 = 0.0;
    for (int k = 0; k < kind.ambientDim; ++k) {
      direction[k] = symmetric(rng);
      length2 += direction[k] * direction[k];
    }
    for (int k = 0; k < kind.ambientDim; ++k) point[k] = jet.x[k] + offset * direction[k] / std::sqrt(length2);
    BruteForceReference reference(cell);
    const RefClosest expected = reference.Closest(point);
    // A start in the answer's basin: the answer's parameters moved by up to
    // 0.05, kept 0.02 off the faces (an answer on the boundary is then
    // reached by steps that leave the domain), or every other trial clamped
    // onto them (the solve then starts on a face, and keeps its constraint
    // only when the descent presses against it).
    const double margin = trial % 4 < 2 ? 0.02 : 0.0;
    double start[3] = {0, 0, 0};
    for (int i = 0; i < pd; ++i) start[i] = std::clamp(expected.ref[i] + 0.05 * symmetric(rng), margin, 1.0 - margin);
    LocalSolveOptions options;
    options.size = cell.size();
    options.checkKkt = true;
    const auto result = LocalSolve(cell.view(), point, start, options);
    SCOPED_TRACE(::testing::Message() << "trial " << trial << "\n" << invmap::testing::Describe(cell));
    ++checked;
    EXPECT_TRUE(result.converged);
    EXPECT_TRUE(result.kkt) << "stopped at a point that is not a KKT point";
    (result.onBoundary ? onBoundary : inside) += 1;
    if (std::abs(std::sqrt(result.squaredDistance) - expected.distance) <= 1e-9 * cell.size()) ++matched;
  }
  EXPECT_GT(onBoundary, 20);
  EXPECT_GT(inside, 20);
  // Distinct minima within 0.05 of each other in the parameters are rare.
  EXPECT_GE(matched, checked * 97 / 100);
}

TEST(LocalSolve, ReleasesAFaceConstraintThatStopsPressing) {
  // The plane z = 0 parametrized as x = u, y = v + (u - 1/2)^2 / 2 (a quad of
  // degrees 2 and 1; the parabola's Bernstein coefficients are 1/8, -1/8,
  // 1/8). From the start (0.95, 0) the point (0.5, 0.1, 0) pulls toward
  // v < 0, so the solve starts on the face v = 0; sliding along it toward
  // u = 0.5, the pull turns into the cell, whose interior holds the point.
  const double a[6] = {1, 0, 0, 1, 0, 0}, b[3] = {0, 0, 0};
  RefCell cell = AffineCell(CellType::Quad, {2, 1, 0}, 3, a, b);
  for (std::size_t c = 0; c < cell.points.size(); c += 3) {
    cell.points[c + 1] += cell.points[c] == 0.5 ? -0.125 : 0.125;
  }
  const double point[3] = {0.5, 0.1, 0.0};
  const double start[2] = {0.95, 0.0};
  LocalSolveOptions options;
  options.size = cell.size();
  options.checkKkt = true;
  const auto result = LocalSolve(cell.view(), point, start, options);
  EXPECT_TRUE(result.converged);
  EXPECT_TRUE(result.kkt);
  EXPECT_FALSE(result.onBoundary);
  EXPECT_LT(std::sqrt(result.squaredDistance), 1e-12);
  EXPECT_NEAR(result.ref[0], 0.5, 1e-9);
  EXPECT_NEAR(result.ref[1], 0.1, 1e-9);
}

TEST(LocalSolve, FaceSolvesFarFromTheOriginConverge) {
  // Quads moved 1e4 away from the origin, where the gradient's rounding
  // noise exceeds the stationarity tolerance; the point lies just beyond
  // the edge v = 0 and the solve starts on that edge. Each solve must stop
  // at its stationary point on the edge within a few iterations, not take
  // tiny final steps until the iteration cap.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> inner(0.2, 0.8);
  int iterations = 0;
  constexpr int kCells = 100;
  for (int trial = 0; trial < kCells; ++trial) {
    RefCell cell = RandomCurvedCell(CellType::Quad, 2 + trial % 2, false, 3, rng);
    for (double& x : cell.points) x += 1e4;
    const double u[2] = {inner(rng), 0.0};
    RefJet jet;
    RefEvaluateJet(cell, u, 1, &jet);
    const double tangentLength =
        std::sqrt(jet.d1[0][1] * jet.d1[0][1] + jet.d1[1][1] * jet.d1[1][1] + jet.d1[2][1] * jet.d1[2][1]);
    double point[3];
    for (int k = 0; k < 3; ++k) point[k] = jet.x[k] - 0.05 * cell.size() * jet.d1[k][1] / tangentLength;
    const double start[2] = {std::clamp(u[0] + 0.1, 0.0, 1.0), 0.0};
    LocalSolveOptions options;
    options.size = cell.size();
    options.checkKkt = true;
    const auto result = LocalSolve(cell.view(), point, start, options);
    EXPECT_TRUE(result.converged) << "trial " << trial << ", " << result.iterations << " iterations";
    iterations += result.iterations;
  }
  EXPECT_LT(iterations, 15 * kCells);
}


TEST(LocalSolve, StepsAsShortAsTheMapNeedsOnAHeavyWeightCurve) {
  // A rational cubic with weights (1, W, 1, 1): for small t it runs along the
  // leg (0,0)-(1,2) as x(t) = 3 W t / (1 + 3 W t) (1, 2) (up to O(t)), so the
  // point (1/2, 1) is the curve's at t ~ 1 / (3 W), 3.3e-16 for W = 1e15:
  // steps of 1e-16 there move the point by a tenth of the cell, and a solve
  // that took them for negligible stopped at t = 0, 1.1 away.
  for (const double heavy : {1e6, 1e10, 1e15}) {
    RefCell cell;
    cell.type = CellType::Line;
    cell.degrees = {3, 0, 0};
    cell.ambientDim = 2;
    cell.points = {0, 0, 1, 2, 2, -1, 3, 2};
    cell.weights = {1, heavy, 1, 1};
    const double point[2] = {0.5, 1.0};
    for (const double start : {0.0, 10.0 / heavy, 1e-3}) {
      LocalSolveOptions options;
      options.size = cell.size();
      options.checkKkt = true;
      const auto result = LocalSolve(cell.view(), point, &start, options);
      EXPECT_LT(std::sqrt(result.squaredDistance), 1e-9 * cell.size()) << "weight " << heavy << ", start " << start;
      EXPECT_NEAR(result.ref[0] * 3 * heavy, 1.0, 1e-3) << "weight " << heavy << ", start " << start;
    }
  }
}

/// The KKT test of cells of line factors (lines, quads, hexes) against the
/// conditions written from their definition on the unit box, with the
/// Jacobian of the independent multinomial evaluation: a free parameter's
/// gradient component within its tolerance (its face basis vector is
/// e_i / sqrt 2), a parameter held at 0 with a gradient not below -tolerance,
/// one held at 1 with a gradient not above +tolerance; parameter i's
/// tolerance is 1e-7 |dx/du_i| |r| (for the basis vector's length) plus
/// 1e-12 size^2. Places inside, on faces and at corners, queries at their own
/// foot (stationary) and off it.
TEST(IsKktPoint, MatchesTheBoxConditionsOnCellsOfLineFactors) {
  std::mt19937_64 rng(20261125);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int stationary = 0, rejected = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const CellType type = trial % 3 == 0 ? CellType::Line : trial % 3 == 1 ? CellType::Quad : CellType::Hex;
    const RefCell cell = RandomCurvedCell(type, 2, trial % 2 == 1, 3, rng);
    const int pd = cell.paramDim();
    double ref[3] = {0, 0, 0};
    for (int i = 0; i < pd; ++i) {
      const double pick = unit(rng);
      ref[i] = pick < 0.2 ? 0.0 : pick < 0.4 ? 1.0 : unit(rng);
    }
    RefJet jet;
    RefEvaluateJet(cell, ref, 1, &jet);
    // The point: the map there plus a random offset (small, so that some
    // places are nearly stationary), or exactly the map there (stationary).
    double point[3];
    const double offset = trial % 4 == 0 ? 0.0 : 0.3 * cell.size() * unit(rng);
    for (int k = 0; k < 3; ++k) point[k] = jet.x[k] + offset * (2.0 * unit(rng) - 1.0);
    invmap::kernels::MapJet kernelJet;
    for (int k = 0; k < 3; ++k) {
      kernelJet.x[k] = jet.x[k];
      for (int i = 0; i < 3; ++i) kernelJet.d1[k][i] = jet.d1[k][i];
    }
    double grad[3] = {0, 0, 0}, column2[3] = {0, 0, 0}, r2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double r = jet.x[k] - point[k];
      r2 += r * r;
      for (int i = 0; i < pd; ++i) {
        grad[i] += jet.d1[k][i] * r;
        column2[i] += jet.d1[k][i] * jet.d1[k][i];
      }
    }
    bool expected = true;
    for (int i = 0; i < pd; ++i) {
      const double slope = 1e-7 * std::sqrt(column2[i]) * std::sqrt(r2);
      const double absolute = 1e-12 * cell.size() * cell.size();
      if (ref[i] == 0.0) {
        expected = expected && grad[i] >= -(slope + absolute);
      } else if (ref[i] == 1.0) {
        expected = expected && grad[i] <= slope + absolute;
      } else {
        expected = expected && std::abs(grad[i]) / std::sqrt(2.0) <= slope / std::sqrt(2.0) + absolute;
      }
    }
    const bool kkt = invmap::kernels::IsKktPoint(cell.view(), kernelJet, point, ref, cell.size());
    ASSERT_EQ(kkt, expected) << "trial " << trial << " ref (" << ref[0] << ", " << ref[1] << ", " << ref[2] << ")";
    stationary += kkt ? 1 : 0;
    rejected += kkt ? 0 : 1;
  }
  // Both verdicts occur, the boundary ones too.
  EXPECT_GT(stationary, 150);
  EXPECT_GT(rejected, 150);
}

}  // namespace
