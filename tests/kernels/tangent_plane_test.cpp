// The tangent-plane exclusion bound (kernels/tangent_plane.h) against an
// independent computation: g = W^2 (|x - p|^2 - level) from the reference
// evaluator, its gradient by central differences, and the plane's least
// value over the domain from the domain's vertices.
// Random curved cells of every type, polynomial and rational, in 2D and 3D,
// at interior and boundary reference points and levels on both sides of
// the plane's sign change.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "kernels/cell_map.h"
#include "kernels/tangent_plane.h"
#include "tests/support/excess_function.h"
#include "tests/support/reference_cell.h"

namespace {

using invmap::kernels::CellType;
using invmap::kernels::EvaluateMap;
using invmap::kernels::JetOrder;
using invmap::kernels::MapJet;
using invmap::kernels::TangentPlaneLowerBound;
using invmap::testing::ControlPointRefLocations;
using invmap::testing::ExcessFunction;
using invmap::testing::ParamDimOf;
using invmap::testing::QueryKind;
using invmap::testing::RandomBoundaryRefPoint;
using invmap::testing::RandomCurvedCell;
using invmap::testing::RandomQuery;
using invmap::testing::RandomRefPoint;
using invmap::testing::RefCell;
using invmap::testing::RefEvaluate;

TEST(TangentPlaneLowerBound, MatchesTheTangentPlaneOfTheExcess) {
  int positive = 0, negative = 0, failures = 0;
  for (CellType type : {CellType::Line, CellType::Tri, CellType::Quad, CellType::Tet, CellType::Hex, CellType::Wedge}) {
    for (const bool rational : {false, true}) {
      for (const int ambientDim : {2, 3}) {
        if (ParamDimOf(type) > ambientDim) continue;
        std::mt19937_64 rng(17 + 8 * static_cast<int>(type) + 2 * rational + ambientDim);
        const RefCell cell = RandomCurvedCell(type, 3, rational, ambientDim, rng);
        const int pd = cell.paramDim();
        // The domain's vertices: the control points of degree one.
        const std::vector<std::array<double, 3>> vertices = ControlPointRefLocations(type, {{1, 1, 1}});
        for (int i = 0; i < 200; ++i) {
          const QueryKind kind = i % 2 ? QueryKind::Far : QueryKind::Boundary;
          const std::array<double, 3> point = RandomQuery(cell, kind, rng).point;
          // Boundary reference points are where the plane excludes a
          // neighbouring cell: flat along the face, rising into the cell.
          std::array<double, 3> ref = i % 3 ? RandomBoundaryRefPoint(type, rng) : RandomRefPoint(type, rng);
          double x[3];
          RefEvaluate(cell, ref.data(), x);
          double f = 0.0;
          for (int k = 0; k < ambientDim; ++k) f += (x[k] - point[k]) * (x[k] - point[k]);
          const double level = f * std::array<double, 4>{0.2, 0.7, 0.95, 1.05}[i % 4];

          const ExcessFunction g(cell, point.data(), level);
          const double h = 1e-6;
          double gradient[3] = {0, 0, 0}, gradientSize = 0.0;
          for (int d = 0; d < pd; ++d) {
            std::array<double, 3> plus = ref, minus = ref;
            plus[d] += h;
            minus[d] -= h;
            gradient[d] = (g(plus.data()) - g(minus.data())) / (2 * h);
            gradientSize += std::abs(gradient[d]);
          }
          const double w2 = g.Weight(ref.data()) * g.Weight(ref.data());
          double expected = std::numeric_limits<double>::infinity();
          for (const std::array<double, 3>& v : vertices) {
            double plane = g(ref.data());
            for (int d = 0; d < pd; ++d) plane += gradient[d] * (v[d] - ref[d]);
            expected = std::min(expected, plane / w2);
          }
          const double tolerance = 1e-7 * (f + level + gradientSize / w2);
          // The bound gives up a little for rounding (cells here have size
          // of order one): a plane positive by less than that may be refused.
          const double rounding = 1e-12 * (1.0 + std::sqrt(f) + gradientSize / w2);

          MapJet jet;
          EvaluateMap(cell.view(), ref.data(), JetOrder::First, &jet);
          const double bound = TangentPlaneLowerBound(cell.shape(), ambientDim, jet, point.data(), ref.data(), level,
                                                      cell.size());
          std::string error;
          if (expected > tolerance + rounding) {
            ++positive;
            if (!(bound <= expected + tolerance && bound >= expected - tolerance - rounding)) {
              error = "positive plane missed or wrong";
            }
          } else if (expected < -tolerance) {
            ++negative;
            if (bound > 0.0) error = "a plane that dips below zero was reported positive (unsound exclusion)";
          }
          if (!error.empty() && failures++ < 10) {
            ADD_FAILURE() << invmap::CellTypeName(type) << (rational ? " rational" : "") << " in "
                          << ambientDim << "D, query " << i << ": " << error << ": bound " << bound << ", expected "
                          << expected << " (tolerance " << tolerance << ")";
          }
        }
      }
    }
  }
  EXPECT_EQ(failures, 0);
  // Both outcomes occur, so neither side of the comparison is vacuous.
  EXPECT_GT(positive, 200);
  EXPECT_GT(negative, 200);
}

}  // namespace
