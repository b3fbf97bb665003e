// The affine hexahedra's frames (engine/hex_frames.h) against the cell
// solver they stand in for: on parallelepipeds of degree 1 and 2, thick and
// nearly flat, every verdict the frame gives on points inside, outside and
// within rounding of the faces is the one CellSolver::SolveInside gives,
// with the same reference coordinates, bit for bit; cells that are no
// parallelepiped get no frame.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "engine/hex_frames.h"
#include "kernels/cell_solver.h"

namespace invmap::testing {
namespace {

using kernels::CellShape;
using kernels::CellSolver;

/// Control points of a Bezier hexahedron of `degree` (net order, first
/// parameter fastest) at x = origin + A u of their reference locations,
/// each moved by `bend` * (u0 u1 (1 - u2)) along x (0: a parallelepiped).
std::vector<double> HexPoints(int degree, const double a[3][3], const double* origin, double bend) {
  std::vector<double> points;
  for (int k = 0; k <= degree; ++k) {
    for (int j = 0; j <= degree; ++j) {
      for (int i = 0; i <= degree; ++i) {
        const double u[3] = {double(i) / degree, double(j) / degree, double(k) / degree};
        for (int r = 0; r < 3; ++r) {
          double x = origin[r] + a[r][0] * u[0] + a[r][1] * u[1] + a[r][2] * u[2];
          if (r == 0) x += bend * u[0] * u[1] * (1 - u[2]);
          points.push_back(x);
        }
      }
    }
  }
  return points;
}

/// Cells and their solvers (each cell's points stay in place: a solver
/// reads them).
struct Cells {
  std::vector<std::vector<double>> points;
  std::vector<CellSolver> solvers;
  void Add(int degree, const double a[3][3], const double* origin, double bend) {
    points.push_back(HexPoints(degree, a, origin, bend));
    kernels::CellView view;
    view.shape = CellShape(kernels::CellType::Hex, {degree, degree, degree});
    view.ambientDim = 3;
    view.points = points.back().data();
    solvers.emplace_back(view);
  }
};

/// Points of reference coordinates spread over [-0.5, 1.5]^3, and others
/// within 1e-16 to 1e-6 of a face (either side), mapped by `a`, `origin`.
std::vector<std::array<double, 3>> Points(const double a[3][3], const double* origin) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> wide(-0.5, 1.5), unit(0.0, 1.0), exponent(-16.0, -6.0);
  std::vector<std::array<double, 3>> points;
  for (int n = 0; n < 4000; ++n) {
    double u[3] = {wide(rng), wide(rng), wide(rng)};
    if (n % 2) {
      for (double& c : u) c = unit(rng);
      const int axis = n % 3;
      const double off = std::pow(10.0, exponent(rng)) * ((n / 2) % 2 ? 1.0 : -1.0);
      u[axis] = (n / 4) % 2 ? 1.0 + off : off;
    }
    std::array<double, 3> x;
    for (int r = 0; r < 3; ++r) x[r] = origin[r] + a[r][0] * u[0] + a[r][1] * u[1] + a[r][2] * u[2];
    points.push_back(x);
  }
  return points;
}

void ExpectFramesAgree(const char* name, int degree, const double a[3][3]) {
  const double origin[3] = {0.3, -1.2, 2.5};
  Cells cells;
  cells.Add(degree, a, origin, 0.0);
  const CellSolver& solver = cells.solvers[0];
  engine::HexFrames frames;
  frames.Build(cells.solvers, [](std::int64_t, int face) { return face; });
  const engine::HexFrame* frame = frames.Of(0);
  ASSERT_NE(frame, nullptr) << name;
  for (int f = 0; f < 6; ++f) EXPECT_EQ(frame->neighbors[f], f) << name;
  int verdicts[3] = {0, 0, 0};
  for (const std::array<double, 3>& p : Points(a, origin)) {
    kernels::CellSolveResult byFrame, bySolver;
    const engine::FrameVerdict verdict = engine::HexFrames::Locate(*frame, p.data(), &byFrame);
    const bool inside = solver.SolveInside(p.data(), nullptr, &bySolver);
    ++verdicts[static_cast<int>(verdict)];
    if (verdict == engine::FrameVerdict::Unsure) continue;
    ASSERT_EQ(inside, verdict == engine::FrameVerdict::Inside) << name << " at " << p[0] << " " << p[1] << " " << p[2];
    for (int i = 0; i < 3; ++i) EXPECT_EQ(byFrame.ref[i], bySolver.ref[i]) << name;
    if (!inside) continue;
    EXPECT_EQ(byFrame.status, bySolver.status) << name;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(byFrame.closest[k], p[k], 1e-12) << name;
  }
  EXPECT_GE(verdicts[static_cast<int>(engine::FrameVerdict::Inside)], 1000) << name;
  EXPECT_GE(verdicts[static_cast<int>(engine::FrameVerdict::Outside)], 1000) << name;
}

TEST(HexFramesTest, VerdictsAreTheSolvers) {
  const double sheared[3][3] = {{1.0, 0.2, 0.1}, {0.1, 0.9, -0.05}, {-0.1, 0.15, 1.1}};
  ExpectFramesAgree("sheared, degree 1", 1, sheared);
  ExpectFramesAgree("sheared, degree 2", 2, sheared);
  // A thin slab (1e-4 thick) and a strongly skewed cell: the closed form's
  // rounding grows, the verdicts must not change.
  const double thin[3][3] = {{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1e-4}};
  ExpectFramesAgree("thin", 1, thin);
  const double skewed[3][3] = {{1.0, 0.999, 0.0}, {0.0, 0.05, 0.0}, {0.0, 0.0, 1.0}};
  ExpectFramesAgree("skewed", 2, skewed);
}

TEST(HexFramesTest, ExitFacesAreTheFacesPassed) {
  // Faces 2f and 2f + 1 are where factor f's barycentrics (1 - u_f, u_f)
  // vanish: beyond u2 = 1 (face 4) by 0.5 and u0 = 0 (face 1) by 0.25,
  // most negative first.
  const double ref[3] = {-0.25, 0.5, 1.5};
  int faces[6];
  ASSERT_EQ(engine::HexFrames::ExitFaces(ref, faces), 2);
  EXPECT_EQ(faces[0], 4);
  EXPECT_EQ(faces[1], 1);
}

TEST(HexFramesTest, OnlyParallelepipedsHaveFrames) {
  const double a[3][3] = {{1.0, 0.2, 0.1}, {0.1, 0.9, -0.05}, {-0.1, 0.15, 1.1}};
  const double origin[3] = {0, 0, 0};
  Cells cells;
  cells.Add(1, a, origin, 0.0);
  cells.Add(1, a, origin, 0.1);
  cells.Add(2, a, origin, 0.0);
  engine::HexFrames frames;
  frames.Build(cells.solvers, [](std::int64_t, int) { return -1; });
  EXPECT_NE(frames.Of(0), nullptr);
  EXPECT_EQ(frames.Of(1), nullptr);
  EXPECT_NE(frames.Of(2), nullptr);
  // Under half the cells framed: no frames at all.
  Cells mostlyBent;
  mostlyBent.Add(1, a, origin, 0.1);
  mostlyBent.Add(1, a, origin, 0.1);
  mostlyBent.Add(1, a, origin, 0.0);
  frames.Build(mostlyBent.solvers, [](std::int64_t, int) { return -1; });
  EXPECT_TRUE(frames.empty());
  EXPECT_EQ(frames.Of(2), nullptr);
}

}  // namespace
}  // namespace invmap::testing
