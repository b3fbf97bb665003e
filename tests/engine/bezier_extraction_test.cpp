#include "engine/bezier_extraction.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "engine/geometry_validation.h"
#include "tests/support/bspline_reference.h"

namespace invmap::engine {
namespace {

using kernels::CellType;

/// What ValidateGeometry finds wrong with `spline` as the one patch of a geometry.
GeometryError ValidateAsGeometry(const BSplinePatch& spline) {
  Geometry geometry;
  geometry.dimension = spline.ambientDim;
  Patch& patch = geometry.patches.emplace_back();
  patch.kind = Patch::Kind::BSpline;
  patch.degrees = spline.degrees;
  patch.knots = spline.knots;
  patch.counts = spline.counts;
  patch.points = spline.controlPoints;
  patch.weights = spline.weights;
  return ValidateGeometry(geometry);
}

/// Relative tolerance between a Bezier cell and the Cox-de Boor evaluation of
/// its patch, scaled by the largest control point coordinate.
constexpr double kRelTol = 1e-12;

/// Bernstein polynomial B_{i,p}(s), written from its definition so that the
/// check shares no code with the extraction.
double Bernstein(int p, int i, double s) {
  double binomial = 1.0;
  for (int k = 1; k <= i; ++k) binomial = binomial * (p - i + k) / k;
  return binomial * std::pow(s, i) * std::pow(1.0 - s, p - i);
}

/// Point of Bezier cell `cell` at reference coordinates ref[0 .. paramDim):
/// tensor-product Bernstein sum, divided by the weight sum when rational.
std::vector<double> EvaluateCell(const ExtractedCells& cells, int cell, const double* ref) {
  const int dim = cells.ambientDim;
  const bool rational = !cells.weights.empty();
  std::vector<double> sum(dim, 0.0);
  double weightSum = 0.0;
  const int sizes[3] = {cells.degrees[0] + 1, cells.degrees[1] + 1, cells.degrees[2] + 1};
  for (int k = 0; k < cells.pointsPerCell; ++k) {
    int rest = k;
    double b = 1.0;
    for (int d = 0; d < cells.paramDim; ++d) {
      b *= Bernstein(cells.degrees[d], rest % sizes[d], ref[d]);
      rest /= sizes[d];
    }
    const std::size_t point = static_cast<std::size_t>(cell) * cells.pointsPerCell + k;
    if (rational) b *= cells.weights[point];
    for (int d = 0; d < dim; ++d) sum[d] += b * cells.points[point * dim + d];
    weightSum += b;
  }
  if (rational) {
    for (double& x : sum) x /= weightSum;
  }
  return sum;
}

/// The spans a reader of docs/formats.md expects: knot indices k in [p, n) with
/// t_k < t_{k+1}.
std::vector<int> NonEmptySpans(const std::vector<double>& knots, int degree, int count) {
  std::vector<int> spans;
  for (int k = degree; k < count; ++k) {
    if (knots[k] < knots[k + 1]) spans.push_back(k);
  }
  return spans;
}

/// Random knot vector of length count + degree + 1 with non-uniform gaps and
/// knot multiplicities 1 .. degree + 1; ends clamped or not at random. The
/// parameter domain [t_p, t_n] is never empty.
std::vector<double> RandomKnots(int degree, int count, std::mt19937& rng) {
  const int length = count + degree + 1;
  std::uniform_int_distribution<int> multiplicity(1, degree + 1);
  std::uniform_real_distribution<double> start(-2.0, 2.0);
  std::uniform_real_distribution<double> logGap(std::log(0.01), std::log(2.0));
  std::bernoulli_distribution coin(0.5);
  for (;;) {
    std::vector<double> t;
    double value = start(rng);
    const auto push = [&](int copies, int limit) {
      for (int m = 0; m < copies && static_cast<int>(t.size()) < limit; ++m) t.push_back(value);
      value += std::exp(logGap(rng));
    };
    const bool clamped = coin(rng);
    push(clamped ? degree + 1 : multiplicity(rng), length);
    const int interiorEnd = clamped ? length - degree - 1 : length;
    while (static_cast<int>(t.size()) < interiorEnd) push(multiplicity(rng), interiorEnd);
    if (clamped) push(degree + 1, length);
    if (t[degree] < t[count]) return t;
  }
}

/// One random-patch configuration.
struct RandomCase {
  const char* name;  ///< Test name suffix.
  int paramDim;      ///< 1 curve, 2 surface, 3 volume.
  int ambientDim;    ///< 2 or 3.
  bool rational;     ///< With random weights.
  int maxDegree;     ///< Degrees are drawn from 1 .. maxDegree.
  int maxExtra;      ///< counts are drawn from p + 1 .. p + 1 + maxExtra.
  int numPatches;    ///< Patches to test.
};

/// Lets GoogleTest print a case by name instead of as raw bytes.
void PrintTo(const RandomCase& c, std::ostream* os) { *os << c.name; }

BSplinePatch RandomPatch(const RandomCase& c, std::mt19937& rng) {
  BSplinePatch patch;
  patch.ambientDim = c.ambientDim;
  int numPoints = 1;
  for (int d = 0; d < c.paramDim; ++d) {
    const int p = std::uniform_int_distribution<int>(1, c.maxDegree)(rng);
    const int n = p + 1 + std::uniform_int_distribution<int>(0, c.maxExtra)(rng);
    patch.degrees.push_back(p);
    patch.counts.push_back(n);
    patch.knots.push_back(RandomKnots(p, n, rng));
    numPoints *= n;
  }
  std::uniform_real_distribution<double> coordinate(-10.0, 10.0);
  for (int k = 0; k < numPoints * c.ambientDim; ++k) patch.controlPoints.push_back(coordinate(rng));
  if (c.rational) {
    std::uniform_real_distribution<double> logWeight(std::log(0.2), std::log(5.0));
    for (int k = 0; k < numPoints; ++k) patch.weights.push_back(std::exp(logWeight(rng)));
  }
  return patch;
}

class RandomPatchTest : public ::testing::TestWithParam<RandomCase> {};

// Every cell, at random and corner reference points, must match the
// Cox-de Boor evaluation of the patch at the mapped parameters, and the cell
// list must be exactly the non-empty spans, u fastest.
TEST_P(RandomPatchTest, CellsMatchCoxDeBoor) {
  const RandomCase& c = GetParam();
  std::mt19937 rng(20240601u + static_cast<unsigned>(c.paramDim * 10 + c.ambientDim) +
                   (c.rational ? 100u : 0u) + static_cast<unsigned>(c.maxDegree) * 1000u);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst = 0.0;
  int numSamples = 0;
  for (int trial = 0; trial < c.numPatches; ++trial) {
    SCOPED_TRACE("patch " + std::to_string(trial));
    const BSplinePatch patch = RandomPatch(c, rng);
    ASSERT_FALSE(ValidateAsGeometry(patch)) << Describe(ValidateAsGeometry(patch));
    const ExtractedCells cells = ExtractBezierCells(patch);

    static constexpr CellType kTypes[] = {CellType::Line, CellType::Quad, CellType::Hex};
    ASSERT_EQ(cells.type, kTypes[c.paramDim - 1]);
    ASSERT_EQ(cells.paramDim, c.paramDim);
    ASSERT_EQ(cells.ambientDim, c.ambientDim);
    int pointsPerCell = 1;
    std::vector<std::vector<int>> spans(3, std::vector<int>{0});
    for (int d = 0; d < 3; ++d) {
      if (d < c.paramDim) {
        ASSERT_EQ(cells.degrees[d], patch.degrees[d]);
        pointsPerCell *= patch.degrees[d] + 1;
        spans[d] = NonEmptySpans(patch.knots[d], patch.degrees[d], patch.counts[d]);
      } else {
        ASSERT_EQ(cells.degrees[d], 0);
      }
    }
    const int numCells = static_cast<int>(spans[0].size() * spans[1].size() * spans[2].size());
    ASSERT_EQ(cells.pointsPerCell, pointsPerCell);
    ASSERT_EQ(cells.numCells, numCells);
    ASSERT_EQ(cells.points.size(),
              static_cast<std::size_t>(numCells) * pointsPerCell * c.ambientDim);
    ASSERT_EQ(cells.weights.size(),
              c.rational ? static_cast<std::size_t>(numCells) * pointsPerCell : 0u);
    for (double w : cells.weights) ASSERT_GT(w, 0.0);
    ASSERT_EQ(cells.spanLo.size(), static_cast<std::size_t>(numCells) * c.paramDim);
    ASSERT_EQ(cells.spanHi.size(), static_cast<std::size_t>(numCells) * c.paramDim);

    double scale = 0.0;
    for (double x : patch.controlPoints) scale = std::max(scale, std::abs(x));
    int cell = 0;
    for (int kw : spans[2]) {
      for (int kv : spans[1]) {
        for (int ku : spans[0]) {
          const int knotSpan[3] = {ku, kv, kw};
          for (int d = 0; d < c.paramDim; ++d) {
            ASSERT_EQ(cells.spanLo[cell * c.paramDim + d], patch.knots[d][knotSpan[d]])
                << "cell " << cell << " direction " << d;
            ASSERT_EQ(cells.spanHi[cell * c.paramDim + d], patch.knots[d][knotSpan[d] + 1])
                << "cell " << cell << " direction " << d;
          }
          // Two corners, then random interior points.
          for (int sample = 0; sample < 6; ++sample) {
            double ref[3], param[3];
            for (int d = 0; d < c.paramDim; ++d) {
              ref[d] = sample == 0 ? 0.0 : sample == 1 ? 1.0 : unit(rng);
              const double lo = cells.spanLo[cell * c.paramDim + d];
              const double hi = cells.spanHi[cell * c.paramDim + d];
              param[d] = lo + (hi - lo) * ref[d];
            }
            const std::vector<double> got = EvaluateCell(cells, cell, ref);
            ++numSamples;
            double want[3];
            invmap::testing::EvaluateBSplinePatch(patch, knotSpan, param, want);
            for (int d = 0; d < c.ambientDim; ++d) {
              const double error = std::abs(got[d] - want[d]);
              worst = std::max(worst, error / scale);
              ASSERT_LE(error, kRelTol * scale)
                  << "cell " << cell << " sample " << sample << " coordinate " << d;
            }
          }
          ++cell;
        }
      }
    }
  }
  std::ostringstream worstText;
  worstText << worst;
  RecordProperty("worst_relative_error", worstText.str());
  RecordProperty("samples", numSamples);
}

INSTANTIATE_TEST_SUITE_P(BezierExtraction, RandomPatchTest,
                         ::testing::Values(RandomCase{"Curve2D", 1, 2, false, 4, 8, 200},
                                           RandomCase{"Curve2DRational", 1, 2, true, 4, 8, 200},
                                           RandomCase{"Curve3D", 1, 3, false, 4, 8, 200},
                                           RandomCase{"Curve3DRational", 1, 3, true, 4, 8, 200},
                                           RandomCase{"CurveHighDegree", 1, 3, true,
                                                      kernels::kMaxDegree, 10, 100},
                                           RandomCase{"Surface2D", 2, 2, false, 4, 5, 60},
                                           RandomCase{"Surface3D", 2, 3, false, 4, 5, 60},
                                           RandomCase{"Surface3DRational", 2, 3, true, 4, 5, 60},
                                           RandomCase{"Volume3D", 3, 3, false, 4, 3, 20},
                                           RandomCase{"Volume3DRational", 3, 3, true, 4, 3, 20}),
                         [](const ::testing::TestParamInfo<RandomCase>& caseInfo) {
                           return std::string(caseInfo.param.name);
                         });

// Cells are the non-empty spans of [t_p, t_n] only, numbered u fastest.
TEST(BezierExtraction, SpanListSkipsEmptySpansAndKnotsOutsideTheDomain) {
  BSplinePatch patch;
  patch.ambientDim = 2;
  patch.degrees = {1, 2};
  patch.counts = {3, 7};
  // v: domain [t_2, t_7] = [2, 5]; spans [2,2], [3,3] (twice) are empty and
  // the knots 0, 1, 6, 7 lie outside the domain.
  patch.knots = {{0, 0, 1, 2, 2}, {0, 1, 2, 2, 3, 3, 3, 5, 6, 7}};
  patch.controlPoints.assign(3 * 7 * 2, 0.0);
  const ExtractedCells cells = ExtractBezierCells(patch);
  EXPECT_EQ(cells.type, CellType::Quad);
  ASSERT_EQ(cells.numCells, 4);
  EXPECT_EQ(cells.spanLo, (std::vector<double>{0, 2, 1, 2, 0, 3, 1, 3}));
  EXPECT_EQ(cells.spanHi, (std::vector<double>{1, 3, 2, 3, 1, 5, 2, 5}));
}

// Uniform unclamped cubic: the textbook Bezier points of one span are
// (P0 + 4 P1 + P2) / 6, (2 P1 + P2) / 3, (P1 + 2 P2) / 3, (P1 + 4 P2 + P3) / 6.
TEST(BezierExtraction, UniformCubicMatchesTextbookFormula) {
  BSplinePatch patch;
  patch.ambientDim = 2;
  patch.degrees = {3};
  patch.counts = {5};
  patch.knots = {{0, 1, 2, 3, 4, 5, 6, 7, 8}};
  patch.controlPoints = {0, 0, 6, 12, 18, -6, 24, 30, 36, 0};
  const ExtractedCells cells = ExtractBezierCells(patch);
  ASSERT_EQ(cells.numCells, 2);
  EXPECT_EQ(cells.spanLo, (std::vector<double>{3, 4}));
  EXPECT_EQ(cells.spanHi, (std::vector<double>{4, 5}));
  const auto point = [&](int k, int d) { return patch.controlPoints[2 * k + d]; };
  for (int cell = 0; cell < 2; ++cell) {
    for (int d = 0; d < 2; ++d) {
      const double p0 = point(cell, d), p1 = point(cell + 1, d);
      const double p2 = point(cell + 2, d), p3 = point(cell + 3, d);
      const double expected[4] = {(p0 + 4 * p1 + p2) / 6, (2 * p1 + p2) / 3, (p1 + 2 * p2) / 3,
                                  (p1 + 4 * p2 + p3) / 6};
      for (int i = 0; i < 4; ++i) {
        EXPECT_NEAR(cells.points[(cell * 4 + i) * 2 + d], expected[i], 1e-13)
            << "cell " << cell << " point " << i << " coordinate " << d;
      }
    }
  }
}

/// Largest | |x| - 1 | over a grid of reference points of every cell.
double MaxCircleError(const ExtractedCells& cells) {
  double worst = 0.0;
  for (int cell = 0; cell < cells.numCells; ++cell) {
    for (int k = 0; k <= 100; ++k) {
      const double s = k / 100.0;
      const std::vector<double> x = EvaluateCell(cells, cell, &s);
      worst = std::max(worst, std::abs(std::hypot(x[0], x[1]) - 1.0));
    }
  }
  return worst;
}

// The quarter circle with a knot inserted at 1/2 (refined by hand in
// homogeneous coordinates): both cells stay on the unit circle and meet at
// 45 degrees by symmetry.
TEST(BezierExtraction, RationalQuarterCircleStaysOnCircle) {
  const double c = std::sqrt(0.5);
  const double w = (1.0 + c) / 2.0;
  BSplinePatch patch;
  patch.ambientDim = 2;
  patch.degrees = {2};
  patch.counts = {4};
  patch.knots = {{0, 0, 0, 0.5, 1, 1, 1}};
  patch.controlPoints = {1, 0, 1, c / (1 + c), c / (1 + c), 1, 0, 1};
  patch.weights = {1, w, w, 1};
  const ExtractedCells cells = ExtractBezierCells(patch);
  ASSERT_EQ(cells.numCells, 2);
  ASSERT_EQ(cells.weights.size(), 6u);
  EXPECT_LE(MaxCircleError(cells), 1e-15);
  // End of cell 0 (point 2) and start of cell 1 (point 3).
  for (int k : {2, 3}) {
    EXPECT_NEAR(cells.points[2 * k], c, 1e-15);
    EXPECT_NEAR(cells.points[2 * k + 1], c, 1e-15);
  }
}

// The standard nine-point NURBS circle, with non-uniform knot spacing (which
// does not change the image): four quarter-circle cells.
TEST(BezierExtraction, RationalFullCircleSplitsIntoQuarters) {
  const double c = std::sqrt(0.5);
  BSplinePatch patch;
  patch.ambientDim = 2;
  patch.degrees = {2};
  patch.counts = {9};
  patch.knots = {{0, 0, 0, 1, 1, 3, 3, 3.5, 3.5, 7, 7, 7}};
  patch.controlPoints = {1, 0, 1, 1, 0, 1, -1, 1, -1, 0, -1, -1, 0, -1, 1, -1, 1, 0};
  patch.weights = {1, c, 1, c, 1, c, 1, c, 1};
  const ExtractedCells cells = ExtractBezierCells(patch);
  ASSERT_EQ(cells.numCells, 4);
  EXPECT_EQ(cells.spanLo, (std::vector<double>{0, 1, 3, 3.5}));
  EXPECT_EQ(cells.spanHi, (std::vector<double>{1, 3, 3.5, 7}));
  EXPECT_LE(MaxCircleError(cells), 1e-15);
  // Clamped C^0 knots: each cell is exactly the patch's own control triple.
  for (int cell = 0; cell < 4; ++cell) {
    for (int i = 0; i < 3; ++i) {
      const int src = 2 * cell + i;
      const int dst = 3 * cell + i;
      EXPECT_NEAR(cells.points[2 * dst], patch.controlPoints[2 * src], 1e-15);
      EXPECT_NEAR(cells.points[2 * dst + 1], patch.controlPoints[2 * src + 1], 1e-15);
      EXPECT_NEAR(cells.weights[dst], patch.weights[src], 1e-15);
    }
  }
}

}  // namespace
}  // namespace invmap::engine
