// The cell search along a valley of (nearly) equal distances: points on or
// next to the axis of a NURBS cylinder or torus, whose closest points form a
// whole circle (or nearly do). The search must certify the answer there, by
// splitting across the valley where the distance's net is loose, not along
// it where the net is exact; splitting by the cell's lengths alone ran out
// of its subdomain budget on every such point (NotCertified, after some
// thousands of subdomains and hundreds of local solves a point). Distances
// are checked against the analytic ones.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "kernels/cell_solver.h"
#include "tests/support/reference_cell.h"

namespace invmap::testing {
namespace {

using kernels::CellSolver;
using kernels::CellSolveResult;
using kernels::CellType;
using kernels::PointStatus;
using kernels::SolveWorkspace;

const double kHalfSqrt2 = std::sqrt(0.5);
/// The quarter circle from (1, 0) to (0, 1): control points and weights.
const double kArcX[3] = {1.0, 1.0, 0.0};
const double kArcY[3] = {0.0, 1.0, 1.0};
const double kArcW[3] = {1.0, kHalfSqrt2, 1.0};

/// A quarter of the cylinder x^2 + y^2 = 1, 0 <= z <= 1: rational quad of
/// degrees (2, 1), u around the axis.
RefCell QuarterCylinder() {
  RefCell cell;
  cell.type = CellType::Quad;
  cell.degrees = {{2, 1, 0}};
  for (int j = 0; j <= 1; ++j) {
    for (int i = 0; i <= 2; ++i) {
      cell.points.insert(cell.points.end(), {kArcX[i], kArcY[i], static_cast<double>(j)});
      cell.weights.push_back(kArcW[i]);
    }
  }
  return cell;
}

/// A quarter around the axis of the torus with radii (big, small), over the
/// quarter of its tube that faces the axis from above: the tube's circle
/// from its top (big, small) to its inner side (big - small, 0) in the
/// (radius, z) plane.
RefCell InnerTorusCell(double big, double small) {
  const double rho[3] = {big, big - small, big - small};
  const double z[3] = {small, small, 0.0};
  RefCell cell;
  cell.type = CellType::Quad;
  cell.degrees = {{2, 2, 0}};
  for (int j = 0; j <= 2; ++j) {
    for (int i = 0; i <= 2; ++i) {
      cell.points.insert(cell.points.end(), {rho[j] * kArcX[i], rho[j] * kArcY[i], z[j]});
      cell.weights.push_back(kArcW[i] * kArcW[j]);
    }
  }
  return cell;
}

/// Solves `points` (3 coordinates each) on `cell` and compares with `exact`.
template <typename Exact>
void ExpectCertifiedAndExact(const char* name, const RefCell& cell, const std::vector<double>& points, Exact exact) {
  const CellSolver solver(cell.view());
  SolveWorkspace ws;
  int uncertified = 0;
  for (size_t k = 0; k < points.size(); k += 3) {
    const double* p = &points[k];
    const CellSolveResult r = solver.Solve(p, nullptr, &ws);
    EXPECT_NEAR(r.distance, exact(p), 1e-9 * cell.size())
        << name << ": point (" << p[0] << ", " << p[1] << ", " << p[2] << ")";
    uncertified += r.status == PointStatus::NotCertified;
  }
  EXPECT_EQ(uncertified, 0) << name << ": of " << points.size() / 3 << " points";
}

/// Points at heights `heights`, on the z axis and at `offsets` from it
/// towards the middle of the quarter.
std::vector<double> AxisPoints(const std::vector<double>& heights, const std::vector<double>& offsets) {
  std::vector<double> points;
  for (const double z : heights) {
    for (const double delta : offsets) points.insert(points.end(), {delta * kHalfSqrt2, delta * kHalfSqrt2, z});
  }
  return points;
}

TEST(ValleySearch, CylinderSeenFromItsAxis) {
  // Inside the height range the closest points are a quarter circle at the
  // point's height; beyond it, the quarter circle of the rim.
  const std::vector<double> points =
      AxisPoints({0.0, 0.1, 0.37, 0.5, 0.93, 1.0, 1.25, -0.6}, {0.0, 1e-12, 1e-9, 1e-6, 1e-3, 0.05});
  ExpectCertifiedAndExact("cylinder", QuarterCylinder(), points, [](const double* p) {
    const double radial = 1.0 - std::hypot(p[0], p[1]);
    const double beyond = p[2] > 1.0 ? p[2] - 1.0 : (p[2] < 0.0 ? -p[2] : 0.0);
    return std::hypot(radial, beyond);
  });
}

TEST(ValleySearch, TorusSeenFromItsAxis) {
  // Above the torus's plane the closest point of the tube's circle faces
  // the axis from above: inside this cell's quarter of the tube.
  const double big = 2.0, small = 0.7;
  const std::vector<double> points = AxisPoints({0.05, 0.3, 1.0, 2.5}, {0.0, 1e-12, 1e-9, 1e-6, 1e-3, 0.05});
  ExpectCertifiedAndExact("torus", InnerTorusCell(big, small), points, [&](const double* p) {
    return std::hypot(big - std::hypot(p[0], p[1]), p[2]) - small;
  });
}

}  // namespace
}  // namespace invmap::testing
