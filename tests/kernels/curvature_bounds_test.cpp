// The quick convexity proof of kernels/curvature_bounds.h: whenever it
// claims g = W^2 (|x(u) - p|^2 - level) convex over a cell, the Hessian of
// g, by finite differences of the reference evaluator, is positive
// semidefinite at every sample of the cell (soundness); on mildly curved
// cells, polynomial and rational, it proves points near the cell, as the
// cell search needs (so the test is not vacuous).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <array>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "kernels/curvature_bounds.h"
#include "tests/support/excess_function.h"
#include "tests/support/finite_differences.h"
#include "tests/support/reference_cell.h"

namespace {

using invmap::kernels::CellType;
using invmap::kernels::CurvatureBounds;
using invmap::kernels::DistanceNets;
using invmap::kernels::HessianStencil;
using invmap::testing::ControlPointRefLocations;
using invmap::testing::ExcessFunction;
using invmap::testing::FiniteDifferenceHessian;
using invmap::testing::ParamDimOf;
using invmap::testing::QueryKind;
using invmap::testing::RandomCurvedCell;
using invmap::testing::RandomQuery;
using invmap::testing::RandomRefPoint;
using invmap::testing::RefCell;
using invmap::testing::RefEvaluate;
using invmap::testing::SmallestEigenvalue;

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
    bounds = std::make_unique<CurvatureBounds>(nets, HessianStencil::Get(nets.shape()));
  }
  DistanceNets nets;
  std::unique_ptr<CurvatureBounds> bounds;
};

TEST(CurvatureBounds, ConvexOnlyWhereEveryHessianIsPositive) {
  int proved = 0, failures = 0;
  for (CellType type : {CellType::Line, CellType::Tri, CellType::Quad, CellType::Tet, CellType::Hex, CellType::Wedge}) {
    for (const int degree : {1, 2, 3, 4}) {
      for (const bool rational : {false, true}) {
        for (const int ambientDim : {2, 3}) {
          if (ParamDimOf(type) > ambientDim) continue;
          std::mt19937_64 rng(7 + 97 * static_cast<int>(type) + 11 * degree + 3 * rational + ambientDim);
          for (int c = 0; c < 3; ++c) {
            const RefCell cell = RandomCurvedCell(type, degree, rational, ambientDim, rng);
            const CellBounds built(cell);
            for (int i = 0; i < 30; ++i) {
              const QueryKind kind = i % 3 == 0 ? QueryKind::Far : (i % 3 == 1 ? QueryKind::Near : QueryKind::Inside);
              const std::array<double, 3> point = RandomQuery(cell, kind, rng).point;
              // Levels as the search uses them: a squared distance to the cell.
              const std::array<double, 3> at = RandomRefPoint(type, rng);
              double x[3];
              RefEvaluate(cell, at.data(), x);
              double f = 0.0;
              for (int k = 0; k < ambientDim; ++k) f += (x[k] - point[k]) * (x[k] - point[k]);
              const double level = f * (0.5 + 0.5 * (i % 2));
              if (!built.bounds->ProvesConvex(point.data(), level)) continue;
              ++proved;
              const ExcessFunction g(cell, point.data(), level);
              // A lattice with the domain's corners, edges and faces (where
              // the bounds' ranges are attained), and random points.
              std::vector<std::array<double, 3>> samples = ControlPointRefLocations(type, {{4, 4, 4}});
              for (int s = 0; s < 60; ++s) samples.push_back(RandomRefPoint(type, rng));
              double least = 1e300, scale = 0.0;
              for (const std::array<double, 3>& u : samples) {
                const Eigen::MatrixXd hessian = FiniteDifferenceHessian(g, cell.paramDim(), u.data(), 1e-4);
                least = std::min(least, SmallestEigenvalue(hessian));
                scale = std::max(scale, hessian.cwiseAbs().maxCoeff());
              }
              if (!(least > -1e-6 * scale) && failures++ < 10) {
                ADD_FAILURE() << invmap::CellTypeName(type) << " degree " << degree
                              << (rational ? " rational" : "") << " in " << ambientDim << "D, cell " << c
                              << ", query " << i << ": proved convex, but a Hessian eigenvalue is " << least
                              << " (largest entry " << scale << ")\n"
                              << invmap::testing::Describe(cell);
              }
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
  // surface are, polynomial and with weights within 1% of one: every point within
  // a fraction of the cell's size of it is proved at the level of its
  // distance to the patch (its Hessian is near J^T J, far from singular).
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> bump(-0.02, 0.02), weight(0.99, 1.01);
  for (const bool rational : {false, true}) {
    int proved = 0, total = 0;
    for (int c = 0; c < 20; ++c) {
      RefCell cell;
      cell.type = CellType::Quad;
      cell.degrees = {{3, 3, 0}};
      cell.ambientDim = 3;
      for (int j = 0; j <= 3; ++j) {
        for (int i = 0; i <= 3; ++i) {
          cell.points.insert(cell.points.end(), {i / 3.0, j / 3.0, bump(rng)});
          if (rational) cell.weights.push_back(weight(rng));
        }
      }
      const CellBounds built(cell);
      for (int i = 0; i < 50; ++i) {
        const std::array<double, 3> u = RandomRefPoint(CellType::Quad, rng);
        const double height = 15.0 * bump(rng);
        const double point[3] = {u[0], u[1], height};
        proved += built.bounds->ProvesConvex(point, height * height) ? 1 : 0;
        ++total;
      }
    }
    EXPECT_EQ(proved, total) << (rational ? "rational" : "polynomial");
  }
}

}  // namespace
