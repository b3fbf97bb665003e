// The quick convexity proof of kernels/curvature_bounds.h: whenever it
// claims |x(u) - p|^2 convex over a cell, the Hessian J^T J + sum_k r_k
// d2x_k, from the reference evaluator, is positive definite at every sample
// of the cell (soundness); on mildly curved cells it proves points near the
// cell, as the cell search needs (so the test is not vacuous); rational
// cells get no proof.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <array>
#include <memory>
#include <random>
#include <string>

#include "kernels/curvature_bounds.h"
#include "tests/support/reference_cell.h"

namespace {

using invmap::kernels::CellType;
using invmap::kernels::CurvatureBounds;
using invmap::kernels::DistanceNets;
using invmap::kernels::HessianStencil;
using invmap::testing::ParamDimOf;
using invmap::testing::QueryKind;
using invmap::testing::RandomCurvedCell;
using invmap::testing::RandomQuery;
using invmap::testing::RandomRefPoint;
using invmap::testing::RefCell;
using invmap::testing::RefEvaluateJet;
using invmap::testing::RefJet;

/// The center of the control points' box (any center serves).
std::array<double, 3> BoxCenter(const RefCell& cell) {
  std::array<double, 3> lo{{1e300, 1e300, 1e300}}, hi{{-1e300, -1e300, -1e300}}, center{{0, 0, 0}};
  for (int c = 0; c < cell.numControlPoints(); ++c) {
    for (int k = 0; k < cell.ambientDim; ++k) {
      lo[k] = std::min(lo[k], cell.points[c * cell.ambientDim + k]);
      hi[k] = std::max(hi[k], cell.points[c * cell.ambientDim + k]);
    }
  }
  for (int k = 0; k < cell.ambientDim; ++k) center[k] = 0.5 * (lo[k] + hi[k]);
  return center;
}

/// The bounds of `cell` as CellSolver builds them: from its DistanceNets
/// around the box center and their shape's HessianStencil.
struct CellBounds {
  explicit CellBounds(const RefCell& cell) {
    const std::array<double, 3> center = BoxCenter(cell);
    nets.Build(cell.view(), center.data());
    bounds = std::make_unique<CurvatureBounds>(cell.view(), nets, HessianStencil::Get(nets.shape()));
  }
  DistanceNets nets;
  std::unique_ptr<CurvatureBounds> bounds;
};

/// Smallest eigenvalue of half the Hessian of |x(u) - point|^2 at u.
double SmallestHessianEigenvalue(const RefCell& cell, const double* u, const double* point) {
  RefJet jet;
  RefEvaluateJet(cell, u, 2, &jet);
  const int pd = cell.paramDim();
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(pd, pd);
  for (int a = 0; a < pd; ++a) {
    for (int b = 0; b < pd; ++b) {
      for (int k = 0; k < cell.ambientDim; ++k) {
        h(a, b) += jet.d1[k][a] * jet.d1[k][b] + (jet.x[k] - point[k]) * jet.d2[k][a][b];
      }
    }
  }
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(h).eigenvalues()(0);
}

TEST(CurvatureBounds, ConvexOnlyWhereEveryHessianIsPositive) {
  int proved = 0, failures = 0;
  for (CellType type : {CellType::Line, CellType::Tri, CellType::Quad, CellType::Tet, CellType::Hex, CellType::Wedge}) {
    for (const int degree : {1, 2, 3, 4}) {
      for (const int ambientDim : {2, 3}) {
        if (ParamDimOf(type) > ambientDim) continue;
        std::mt19937_64 rng(7 + 97 * static_cast<int>(type) + 11 * degree + ambientDim);
        for (int c = 0; c < 4; ++c) {
          const RefCell cell = RandomCurvedCell(type, degree, false, ambientDim, rng);
          const CellBounds built(cell);
          const CurvatureBounds& bounds = *built.bounds;
          for (int i = 0; i < 40; ++i) {
            const QueryKind kind = i % 3 == 0 ? QueryKind::Far : (i % 3 == 1 ? QueryKind::Near : QueryKind::Inside);
            const std::array<double, 3> point = RandomQuery(cell, kind, rng).point;
            if (!bounds.ProvesConvex(point.data())) continue;
            ++proved;
            double least = 1e300;
            for (int s = 0; s < 200; ++s) {
              const std::array<double, 3> u = RandomRefPoint(type, rng);
              least = std::min(least, SmallestHessianEigenvalue(cell, u.data(), point.data()));
            }
            if (!(least > 0.0) && failures++ < 10) {
              ADD_FAILURE() << invmap::kernels::CellTypeName(type) << " degree " << degree << " in " << ambientDim
                            << "D, cell " << c << ", query " << i
                            << ": proved convex, but a Hessian eigenvalue is " << least << "\n"
                            << invmap::testing::Describe(cell);
            }
          }
        }
      }
    }
  }
  EXPECT_EQ(failures, 0);
  EXPECT_GT(proved, 500);  // the test above is not vacuous
}

TEST(CurvatureBounds, ProvesPointsNearMildlyCurvedSurfaces) {
  // Bicubic patches a little off a plane, as the spans of a smooth spline
  // surface are: every point within a fraction of the cell's size of it is
  // proved (its Hessian is near J^T J, far from singular).
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> bump(-0.02, 0.02);
  int proved = 0, total = 0;
  for (int c = 0; c < 20; ++c) {
    RefCell cell;
    cell.type = CellType::Quad;
    cell.degrees = {{3, 3, 0}};
    cell.ambientDim = 3;
    for (int j = 0; j <= 3; ++j) {
      for (int i = 0; i <= 3; ++i) cell.points.insert(cell.points.end(), {i / 3.0, j / 3.0, bump(rng)});
    }
    const CellBounds built(cell);
    const CurvatureBounds& bounds = *built.bounds;
    for (int i = 0; i < 50; ++i) {
      const std::array<double, 3> u = RandomRefPoint(CellType::Quad, rng);
      const double point[3] = {u[0], u[1], 0.3 * bump(rng) / 0.02};
      proved += bounds.ProvesConvex(point) ? 1 : 0;
      ++total;
    }
  }
  EXPECT_EQ(proved, total);
}

TEST(CurvatureBounds, RationalCellsAreNotProved) {
  std::mt19937_64 rng(3);
  const RefCell cell = RandomCurvedCell(CellType::Quad, 2, true, 3, rng);
  const CellBounds built(cell);
  EXPECT_FALSE(built.bounds->ProvesConvex(BoxCenter(cell).data()));
}

}  // namespace
