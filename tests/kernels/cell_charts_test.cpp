// Charts of a cell (kernels/cell_charts.h) and what they are for: points of
// a rational cell whose weights lie far apart, at parameters within 1e-9 to
// 1e-15 of a face (where the heavy weight's reach ends), are found on the
// cell. The points are built by this file's own evaluator, in long double
// from full barycentric coordinates, so a coordinate of 1e-15 next to a
// face the reference coordinates leave implicit (lambda_0 = 1 - sum) is
// exact; the answer is known: distance zero.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "kernels/cell_charts.h"
#include "kernels/cell_solver.h"

namespace {

using invmap::kernels::Barycentric;
using invmap::kernels::CellCharts;
using invmap::kernels::CellShape;
using invmap::kernels::CellSolver;
using invmap::kernels::CellSolveResult;
using invmap::kernels::CellType;
using invmap::kernels::CellView;
using invmap::kernels::EvaluateMap;
using invmap::kernels::JetOrder;
using invmap::kernels::MapJet;
using invmap::kernels::SolveWorkspace;
using Real = long double;

/// A simplex factor's multi-indices (a0, .., ad) in docs/formats.md order: a1
/// fastest, then a2, then a3; a0 = p - the others.
std::vector<std::array<int, 4>> SimplexMultiIndices(int dim, int p) {
  std::vector<std::array<int, 4>> out;
  for (int a3 = 0; a3 <= (dim > 2 ? p : 0); ++a3) {
    for (int a2 = 0; a2 <= (dim > 1 ? p - a3 : 0); ++a2) {
      for (int a1 = 0; a1 <= p - a2 - a3; ++a1) out.push_back({p - a1 - a2 - a3, a1, a2, a3});
    }
  }
  return out;
}

/// Bernstein polynomial of multi-index a at barycentric lambda (degree p).
Real Bernstein(const std::array<int, 4>& a, const Real* lambda, int dim, int p) {
  Real value = std::tgamma(Real(p + 1));
  for (int i = 0; i <= dim; ++i) value *= std::pow(lambda[i], Real(a[i])) / std::tgamma(Real(a[i] + 1));
  return value;
}

/// A cell of simplex factors (dims, degrees), its rational map evaluated at
/// full barycentric coordinates per factor.
struct TestCell {
  CellType type;
  std::vector<int> dims, degrees;
  int ambientDim = 3;
  std::vector<double> points, weights;

  CellView View() const {
    std::array<int, 3> d{0, 0, 0};
    for (size_t f = 0; f < degrees.size(); ++f) d[f] = degrees[f];
    CellView view;
    view.shape = CellShape(type, d);
    view.ambientDim = ambientDim;
    view.points = points.data();
    view.weights = weights.data();
    return view;
  }
  std::array<Real, 3> Evaluate(const std::vector<std::array<Real, 4>>& lambda) const {
    // Control point c = product over factors of their multi-indices, first factor fastest.
    std::vector<std::vector<std::array<int, 4>>> multis;
    for (size_t f = 0; f < dims.size(); ++f) multis.push_back(SimplexMultiIndices(dims[f], degrees[f]));
    std::array<Real, 3> x{0, 0, 0};
    Real w = 0;
    const size_t n = weights.size();
    for (size_t c = 0; c < n; ++c) {
      size_t rest = c;
      Real b = weights[c];
      for (size_t f = 0; f < dims.size(); ++f) {
        const auto& a = multis[f][rest % multis[f].size()];
        rest /= multis[f].size();
        b *= Bernstein(a, lambda[f].data(), dims[f], degrees[f]);
      }
      w += b;
      for (int k = 0; k < ambientDim; ++k) x[k] += b * points[c * ambientDim + k];
    }
    for (Real& xk : x) xk /= w;
    return x;
  }
};

/// A random cell near the unit box with one control point `heavy` times the
/// others' weights (ordinary weights 0.5 to 2).
TestCell RandomHeavyCell(CellType type, std::vector<int> dims, std::vector<int> degrees, int ambientDim,
                         double heavy, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  TestCell cell{type, dims, degrees, ambientDim, {}, {}};
  size_t n = 1;
  for (size_t f = 0; f < dims.size(); ++f) n *= SimplexMultiIndices(dims[f], degrees[f]).size();
  for (size_t c = 0; c < n; ++c) {
    for (int k = 0; k < ambientDim; ++k) cell.points.push_back(unit(rng));
    cell.weights.push_back(0.5 + 1.5 * unit(rng));
  }
  cell.weights[rng() % n] *= heavy;
  return cell;
}

struct Case {
  CellType type;
  std::vector<int> dims, degrees;
  int ambientDim;
};

const Case kCases[] = {
    {CellType::Line, {1}, {3}, 2},      {CellType::Tri, {2}, {3}, 2},      {CellType::Tri, {2}, {2}, 3},
    {CellType::Quad, {1, 1}, {2, 3}, 3}, {CellType::Tet, {3}, {2}, 3},      {CellType::Hex, {1, 1, 1}, {2, 2, 2}, 3},
    {CellType::Wedge, {2, 1}, {2, 1}, 3},
};

/// Random barycentric coordinates per factor, one of them (any, lambda_0
/// included) set to `small` and the rest rescaled to sum to one.
std::vector<std::array<Real, 4>> LayerPoint(const std::vector<int>& dims, Real small, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.05, 1.0);
  std::vector<std::array<Real, 4>> lambda;
  for (int dim : dims) {
    std::array<Real, 4> l{0, 0, 0, 0};
    Real sum = 0;
    for (int i = 0; i <= dim; ++i) sum += (l[i] = unit(rng));
    const int tiny = static_cast<int>(rng() % (dim + 1));
    const Real others = sum - l[tiny];
    for (int i = 0; i <= dim; ++i) l[i] = i == tiny ? small : l[i] / others * (1 - small);
    lambda.push_back(l);
  }
  return lambda;
}

TEST(CellCharts, EveryChartIsTheSameMap) {
  std::mt19937_64 rng(2026112501);
  for (const Case& c : kCases) {
    const TestCell cell = RandomHeavyCell(c.type, c.dims, c.degrees, c.ambientDim, 10.0, rng);
    const CellView view = cell.View();
    const CellCharts charts(view);
    int count = 1;
    for (int d : c.dims) count *= d + 1;
    for (int trial = 0; trial < 20; ++trial) {
      const auto lambda = LayerPoint(c.dims, 0.1L, rng);
      Barycentric b;
      for (size_t f = 0; f < c.dims.size(); ++f) {
        for (int i = 0; i < 4; ++i) b.lambda[f][i] = static_cast<double>(lambda[f][i]);
      }
      const std::array<Real, 3> expected = cell.Evaluate(lambda);
      for (int chart = 0; chart < count; ++chart) {
        double ref[3] = {0, 0, 0};
        charts.FromBarycentric(chart, b, ref);
        MapJet jet;
        EvaluateMap(charts.view(chart), ref, JetOrder::Value, &jet);
        for (int k = 0; k < c.ambientDim; ++k) {
          EXPECT_NEAR(jet.x[k], static_cast<double>(expected[k]), 1e-12)
              << invmap::CellTypeName(c.type) << " chart " << chart;
        }
        const Barycentric back = charts.ToBarycentric(chart, ref);
        for (size_t f = 0; f < c.dims.size(); ++f) {
          for (int i = 0; i <= c.dims[f]; ++i) EXPECT_NEAR(back.lambda[f][i], b.lambda[f][i], 1e-15);
        }
      }
      EXPECT_EQ(charts.ChartFor(b) == 0, [&] {
        for (size_t f = 0; f < c.dims.size(); ++f) {
          for (int i = 1; i <= c.dims[f]; ++i) {
            if (b.lambda[f][i] > b.lambda[f][0]) return false;
          }
        }
        return true;
      }());
    }
  }
}

TEST(CellCharts, PointsInTheLayerOfAHeavyWeightAreFound) {
  std::mt19937_64 rng(2026112502);
  SolveWorkspace ws;
  int failures = 0;
  for (const Case& c : kCases) {
    for (const double heavy : {1e8, 1e12}) {
      const TestCell cell = RandomHeavyCell(c.type, c.dims, c.degrees, c.ambientDim, heavy, rng);
      const CellSolver solver(cell.View());
      for (int trial = 0; trial < 40; ++trial) {
        const Real small = std::pow(Real(10), -Real(9 + trial % 7));
        const std::array<Real, 3> x = cell.Evaluate(LayerPoint(c.dims, small, rng));
        const double point[3] = {static_cast<double>(x[0]), static_cast<double>(x[1]), static_cast<double>(x[2])};
        const CellSolveResult r = solver.Solve(point, nullptr, &ws);
        if (!(r.distance <= 1e-9 * solver.size()) && failures++ < 10) {
          ADD_FAILURE() << invmap::CellTypeName(c.type) << " weight " << heavy << ", coordinate " << static_cast<double>(small)
                        << ": distance " << r.distance << " for a point of the cell";
        }
      }
    }
  }
  EXPECT_EQ(failures, 0);
}

}  // namespace
