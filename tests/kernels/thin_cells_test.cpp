// Cells much longer than they are thick (the prisms and hexes of a CFD
// boundary layer, a narrow ribbon of a surface): points of the cell, built
// by the test's own evaluator from parameters inside the domain, are found
// at distance zero with those parameters. The local solve used to judge the
// slope along the thickness by the cell's size: an inside point 1e-8 of the
// size away from a face was put on the face (QA: hexes 1e-6 thick, ribbons
// 1e-7 wide). The answer is known by construction; the solver promises it
// to kDistanceTolerance of the cell's size (1e-3 of the thinnest cell here).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>

#include "kernels/cell_solver.h"
#include "kernels/kkt_point.h"
#include "kernels/local_solver.h"
#include "kernels/tolerances.h"
#include "tests/support/reference_cell.h"

namespace {

using invmap::kernels::CellSolver;
using invmap::kernels::CellSolveResult;
using invmap::kernels::CellType;
using invmap::kernels::EvaluateMap;
using invmap::kernels::IsKktPoint;
using invmap::kernels::JetOrder;
using invmap::kernels::kDistanceTolerance;
using invmap::kernels::MapJet;
using invmap::kernels::SolveWorkspace;
using invmap::testing::ControlPointRefLocations;
using invmap::testing::Describe;
using invmap::testing::RefCell;
using invmap::testing::RefEvaluate;

/// A gently curved sheet over the first two parameters, `thickness` thick
/// along the third (a volume), or a ribbon `thickness` wide along the second
/// (a surface): the control points are the bent map at the control points'
/// reference places, so the cell is as thin as the map.
RefCell ThinCell(CellType type, std::array<int, 3> degrees, double thickness) {
  RefCell cell;
  cell.type = type;
  cell.degrees = degrees;
  const bool volume = cell.paramDim() == 3;
  for (const std::array<double, 3>& at : ControlPointRefLocations(type, degrees)) {
    const double s = at[0], t = volume ? at[1] : thickness * at[1], r = volume ? at[2] : 0.0;
    cell.points.insert(cell.points.end(), {s + 0.2 * t * t, t + 0.1 * std::sin(2 * s),
                                           0.3 * (s - 0.5) * (s - 0.5) + 0.2 * s * t + thickness * r * (1 + 0.3 * s)});
  }
  return cell;
}

/// Parameters inside the domain of `type`: a third of them within 1e-3 of
/// the face the thin direction leaves (r = 0 for volumes, t = 0 for surfaces).
std::array<double, 3> InsideParameters(CellType type, bool nearFace, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.02, 0.98);
  std::array<double, 3> u{unit(rng), unit(rng), unit(rng)};
  if (type == CellType::Tet) {
    // A random point of the simplex: the sorted cuts of [0, 1].
    std::array<double, 3> cuts = u;
    std::sort(cuts.begin(), cuts.end());
    u = {cuts[0], cuts[1] - cuts[0], cuts[2] - cuts[1]};
  } else if (type == CellType::Wedge && u[0] + u[1] > 1.0) {
    u[0] = 1.0 - u[0];
    u[1] = 1.0 - u[1];
  }
  const int thin = type == CellType::Quad ? 1 : 2;
  if (nearFace) u[thin] *= 1e-3;
  return u;
}

double Distance(const double* a, const double* b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

struct ThinCase {
  CellType type;
  std::array<int, 3> degrees;
};

TEST(ThinCells, PointsOfTheCellAreFoundOnItWithTheirParameters) {
  const ThinCase cases[] = {{CellType::Hex, {1, 1, 1}},   {CellType::Hex, {2, 2, 1}}, {CellType::Hex, {3, 3, 2}},
                            {CellType::Tet, {1, 0, 0}},   {CellType::Tet, {2, 0, 0}}, {CellType::Wedge, {2, 1, 0}},
                            {CellType::Wedge, {3, 2, 0}}, {CellType::Quad, {3, 3, 0}}};
  std::mt19937_64 rng(2026);
  SolveWorkspace ws;
  int failures = 0, checked = 0;
  for (const ThinCase& c : cases) {
    for (const double thickness : {1e-3, 1e-5, 1e-6, 1e-7, 1e-8}) {
      const RefCell cell = ThinCell(c.type, c.degrees, thickness);
      const CellSolver solver(cell.view());
      const double tolerance = kDistanceTolerance * cell.size();
      for (int i = 0; i < 60; ++i) {
        const std::array<double, 3> params = InsideParameters(c.type, i % 3 == 0, rng);
        double query[3] = {0, 0, 0};
        RefEvaluate(cell, params.data(), query);
        const CellSolveResult r = solver.Solve(query, nullptr, &ws);
        // The reported parameters, mapped by the test's own evaluator, give
        // the query point back: the preimage is exact, not just the distance.
        double back[3] = {0, 0, 0};
        RefEvaluate(cell, r.ref, back);
        ++checked;
        if ((r.distance <= tolerance && Distance(back, query) <= tolerance) || failures++ >= 5) continue;
        ADD_FAILURE() << "thickness " << thickness << ", query " << i << " at (" << params[0] << ", " << params[1]
                      << ", " << params[2] << "): distance " << r.distance << " at (" << r.ref[0] << ", "
                      << r.ref[1] << ", " << r.ref[2] << "), its image " << Distance(back, query)
                      << " from the query\n"
                      << Describe(cell);
      }
    }
  }
  EXPECT_EQ(failures, 0) << "of " << checked;
}

TEST(ThinCells, TheKktTestJudgesTheThicknessByItsOwnScale) {
  // QA's trilinear hex 1e-6 thick, a point of it 0.0139 of the way up its
  // thickness, and the point of the face r = 0 nearest to it, 1.7e-8 away,
  // where the solve used to stop. Along r the slope r . J e_r is 1e-6 of
  // what the same residual gives along s or t: judged by the cell's size it
  // passed for zero.
  RefCell cell;
  cell.type = CellType::Hex;
  cell.degrees = {1, 1, 1};
  cell.points = {0.0, 0.0, 0.075, 1.0, 0.09092974268256816, 0.075, 0.2, 1.0, 0.075,
                 1.2, 1.0909297426825681, 0.275, 0.0, 0.0, 0.075001, 1.0, 0.09092974268256816, 0.07500129999999999,
                 0.2, 1.0, 0.075001, 1.2, 1.0909297426825681, 0.2750013};
  const double inside[3] = {0.74924891029795293, 0.85343320297384562, 0.013881125498560021};
  double query[3];
  RefEvaluate(cell, inside, query);
  const double onFace[3] = {0.74924891257015069, 0.85343320469482897, 0.0};
  MapJet jet;
  EvaluateMap(cell.view(), onFace, JetOrder::First, &jet);
  ASSERT_GT(Distance(jet.x, query), 1e-9);
  EXPECT_FALSE(IsKktPoint(cell.view(), jet, query, onFace, cell.size()));
  // The point itself is one (distance zero).
  EvaluateMap(cell.view(), inside, JetOrder::First, &jet);
  EXPECT_TRUE(IsKktPoint(cell.view(), jet, query, inside, cell.size()));
}

}  // namespace
