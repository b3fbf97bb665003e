// Coreform Cubit's Bezier extraction files (LS-DYNA BEXT, current JSON,
// Exodus BEX), written here from B-spline and NURBS geometries whose
// answers are known: a cubic curve with a double knot, a "U-spline-like"
// surface of two blocks of different degrees, a rational half annulus
// (exact circles). Every element's cell is compared with the spline itself
// (Cox-de Boor at the element's knot values); inverted points with the
// annulus' analytic distances; malformed files name the file and the line,
// element or block.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "fem/cubit_bext_reader.h"
#include "fem/cubit_json_reader.h"
#include "fem/exodus_reader.h"
#include "io/input_error.h"
#include "tests/fem/extraction_model.h"
#include "tests/fem/fem_test_support.h"
#include "tests/io/io_scratch.h"

namespace invmap::testing {
namespace {

using io::scratch::ScratchDir;

/// A planar-ish cubic curve with a double knot (C1 at t = 2): 4 elements.
TestSpline CubicCurve() {
  TestSpline s;
  s.degrees = {3};
  s.knots = {{0, 0, 0, 0, 1, 2, 2, 3, 4, 4, 4, 4}};
  s.counts = {8};
  s.points = {{0, 0, 0}, {1, 2, 0.5}, {2, -1, 0}, {3, 1, 1}, {4, 0, 0.2}, {5, 2, -0.5}, {6, 1, 0}, {7, 0, 0.3}};
  return s;
}

/// Two surface blocks of different degrees: biquadratic 2 x 2 elements and
/// bicubic 1 x 2 elements, non-uniform knots.
std::vector<TestSpline> TwoDegreeSurface() {
  TestSpline a;
  a.degrees = {2, 2};
  a.knots = {{0, 0, 0, 0.4, 1, 1, 1}, {0, 0, 0, 0.5, 1, 1, 1}};
  a.counts = {4, 4};
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) a.points.push_back({double(i), double(j), 0.2 * std::sin(i + 2.0 * j)});
  }
  TestSpline b;
  b.degrees = {3, 3};
  b.knots = {{0, 0, 0, 0, 1, 1, 1, 1}, {0, 0, 0, 0, 0.3, 1, 1, 1, 1}};
  b.counts = {4, 5};
  for (int j = 0; j < 5; ++j) {
    for (int i = 0; i < 4; ++i) b.points.push_back({4.0 + i, 0.75 * j, 0.3 * std::cos(i - j)});
  }
  return {a, b};
}

/// A NURBS half annulus solid: radii 1 to 2, angle 0 to pi (two exact
/// quarter circles, degree 2), height 0 to 1: 2 rational hex elements.
TestSpline HalfAnnulus() {
  TestSpline s;
  s.degrees = {2, 1, 1};
  s.knots = {{0, 0, 0, 0.5, 0.5, 1, 1, 1}, {0, 0, 1, 1}, {0, 0, 1, 1}};
  s.counts = {5, 2, 2};
  const double h = std::sqrt(0.5);
  const double ring[5][3] = {{1, 0, 1}, {1, 1, h}, {0, 1, 1}, {-1, 1, h}, {-1, 0, 1}};  // x, y, weight
  for (int k = 0; k < 2; ++k) {
    for (int j = 0; j < 2; ++j) {
      for (const auto& c : ring) {
        const double r = 1.0 + j;
        s.points.push_back({r * c[0], r * c[1], double(k)});
        s.weights.push_back(c[2]);
      }
    }
  }
  return s;
}

enum class Format { Bext, Json, Exodus };

std::string FormatName(Format f) { return f == Format::Bext ? "bext" : f == Format::Json ? "json" : "exo"; }

/// Writes the model in `format` and reads it back with invmap's reader.
FieldGeometry WriteAndRead(const ScratchDir& dir, const TestModel& model, Format format) {
  const std::string path = dir.Path("model." + FormatName(format));
  switch (format) {
    case Format::Bext:
      dir.Write("model.bext", BextText(model));
      return fem::ReadCubitBext(path);
    case Format::Json:
      dir.Write("model.json", CubitJsonText(model));
      EXPECT_TRUE(fem::LooksLikeCubitJson(path));
      return fem::ReadCubitJson(path);
    case Format::Exodus:
      EXPECT_TRUE(WriteExodusBex(path, model));
      return fem::ReadExodus(path, {});
  }
  return {};
}

/// (patch, cell) of every model element: BEXT has one patch of all
/// elements; JSON (block_elem_map) and Exodus one patch per spline block.
std::vector<std::pair<int, int>> CellsOf(const TestModel& model, Format format) {
  std::vector<std::pair<int, int>> cells;
  std::vector<int> perSpline(model.splines.size(), 0);
  for (std::size_t e = 0; e < model.elements.size(); ++e) {
    const int s = model.elements[e].spline;
    cells.push_back(format == Format::Bext ? std::make_pair(0, static_cast<int>(e)) : std::make_pair(s, perSpline[s]++));
  }
  return cells;
}

void ExpectCellsEqualSpline(const TestModel& model, Format format, double tolerance) {
  const ScratchDir dir;
  const FieldGeometry read = WriteAndRead(dir, model, format);
  const std::vector<std::pair<int, int>> cells = CellsOf(model, format);
  EXPECT_EQ(read.geometry.patches.size(), format == Format::Bext ? 1u : model.splines.size());
  std::mt19937 rng(5);
  for (std::size_t e = 0; e < model.elements.size(); ++e) {
    const TestElement& element = model.elements[e];
    const TestSpline& spline = model.splines[element.spline];
    const CellType type = spline.degrees.size() == 1 ? CellType::Line : spline.degrees.size() == 2 ? CellType::Quad
                                                                                                     : CellType::Hex;
    for (int trial = 0; trial < 12; ++trial) {
      const std::array<double, 3> s = RandomReferencePoint(type, rng);
      const std::array<double, 3> expected = spline.Evaluate(element.spans, model.KnotValues(element, s));
      const std::vector<double> x = EvaluateAt(read.geometry, nullptr, cells[e].first, cells[e].second, s);
      ASSERT_EQ(x.size(), static_cast<std::size_t>(read.geometry.dimension));
      for (int k = 0; k < read.geometry.dimension; ++k) {
        EXPECT_NEAR(x[k], expected[k], tolerance) << FormatName(format) << " element " << e << " coordinate " << k;
      }
    }
  }
}

class CubitFormatTest : public ::testing::TestWithParam<Format> {};

TEST_P(CubitFormatTest, CurveElementsAreTheSpline) { ExpectCellsEqualSpline(Extract({CubicCurve()}), GetParam(), 1e-12); }

TEST_P(CubitFormatTest, BlocksOfDifferentDegreesAreTheSplines) {
  ExpectCellsEqualSpline(Extract(TwoDegreeSurface()), GetParam(), 1e-12);
}

TEST_P(CubitFormatTest, RationalElementsAreTheNurbs) { ExpectCellsEqualSpline(Extract({HalfAnnulus()}), GetParam(), 1e-12); }

// Points inside and around the half annulus get their analytic distances
// and closest points; the reported parameters map back to the point.
TEST_P(CubitFormatTest, HalfAnnulusAnswersAreAnalytic) {
  const ScratchDir dir;
  const TestModel model = Extract({HalfAnnulus()});
  const FieldGeometry read = WriteAndRead(dir, model, GetParam());
  BuildResult built = Manifold::Build(read.geometry);
  ASSERT_TRUE(built.error.empty()) << built.error;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> xyz, distance;
  for (int i = 0; i < 300; ++i) {
    const double theta = 0.05 + 3.04 * u(rng);
    const int kind = i % 3;  // inside, beyond the outer radius, above the top
    const double r = kind == 1 ? 2.0 + 0.5 * u(rng) : 1.05 + 0.9 * u(rng);
    const double z = kind == 2 ? 1.0 + 0.4 * u(rng) : 0.05 + 0.9 * u(rng);
    xyz.insert(xyz.end(), {r * std::cos(theta), r * std::sin(theta), z});
    distance.push_back(kind == 0 ? 0.0 : kind == 1 ? r - 2.0 : z - 1.0);
  }
  Results results;
  ASSERT_EQ(built.manifold.Invert(PointsView::Interleaved(xyz.data(), distance.size(), 3), {}, &results), Error::Ok);
  for (std::size_t i = 0; i < distance.size(); ++i) {
    ASSERT_EQ(results.status[i], Status::Found);
    EXPECT_NEAR(results.distance[i], distance[i], 1e-10) << "point " << i;
    // The parameters reported are the element's: the element maps them to the closest point.
    const std::array<double, 3> s{results.params[3 * i], results.params[3 * i + 1], results.params[3 * i + 2]};
    const int cell = static_cast<int>(results.cell[i]);
    const std::array<double, 3> x = model.splines[0].Evaluate(model.elements[cell].spans,
                                                              model.KnotValues(model.elements[cell], s));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(x[k], results.closest[3 * i + k], 1e-10) << "point " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(CubitFormats, CubitFormatTest, ::testing::Values(Format::Bext, Format::Json, Format::Exodus),
                         [](const ::testing::TestParamInfo<Format>& p) { return FormatName(p.param); });

// A flat geometry is 2D in every format.
TEST(CubitExtraction, FlatSurfaceIsTwoDimensional) {
  TestSpline flat = TwoDegreeSurface()[0];
  for (auto& p : flat.points) p[2] = 0.0;
  const ScratchDir dir;
  dir.Write("flat.bext", BextText(Extract({flat})));
  EXPECT_EQ(fem::ReadCubitBext(dir.Path("flat.bext")).geometry.dimension, 2);
}

/// `text` with line `line` (1-based) replaced.
std::string ReplaceLine(const std::string& text, int line, const std::string& replacement) {
  std::istringstream in(text);
  std::string out, current;
  for (int n = 1; std::getline(in, current); ++n) out += (n == line ? replacement : current) + "\n";
  return out;
}

TEST(CubitExtraction, BadBextFilesNameFileAndLine) {
  const ScratchDir dir;
  const std::string good = BextText(Extract({CubicCurve()}));
  ExpectInputError([&] { fem::ReadCubitBext(dir.Write("a.bext", ReplaceLine(good, 1, "B E X T 3.0"))); },
              {"a.bext:1:", "version 3.0"});
  ExpectInputError([&] { fem::ReadCubitBext(dir.Write("b.bext", "hello\n")); }, {"b.bext:1:", "B E X T 2.0"});
  // Bytes that are not text: the binary form, refused as such.
  ExpectInputError([&] { fem::ReadCubitBext(dir.Write("binary.bext", std::string("\x01\x00\x00\x00" "BEXT\x02", 9))); },
                   {"binary.bext:1:", "binary LS-DYNA Bezier extraction form is not read"});
  // Line 6 is the first control point.
  ExpectInputError([&] { fem::ReadCubitBext(dir.Write("c.bext", ReplaceLine(good, 6, "0 0 zero 1"))); },
              {"c.bext:6:", "'zero'"});
  // Cut inside the last coefficient vector.
  ExpectInputError([&] { fem::ReadCubitBext(dir.Write("d.bext", good.substr(0, good.size() - 40))); },
              {"d.bext:", "unexpected end of file"});
  // The first element's control point ids (line after the block header).
  std::istringstream in(good);
  std::string line;
  int n = 0, idsLine = 0;
  while (std::getline(in, line)) {
    ++n;
    if (line.rfind("1 4 4 4 3", 0) == 0) idsLine = n + 1;
  }
  ASSERT_GT(idsLine, 0);
  ExpectInputError([&] { fem::ReadCubitBext(dir.Write("e.bext", ReplaceLine(good, idsLine, "1 2 3 99"))); },
              {"e.bext", "element 1", "control point 98 out of range"});
  ExpectInputError([&] { fem::ReadCubitBext(dir.Write("f.bext", ReplaceLine(good, idsLine - 1, "2 4 4 4 3"))); },
              {"f.bext:" + std::to_string(idsLine - 1) + ":", "element type 2"});
}

TEST(CubitExtraction, BadJsonFilesNameFileAndPath) {
  const ScratchDir dir;
  ExpectInputError([&] { fem::ReadCubitJson(dir.Write("a.json", "{\n\"patch_id\": 0,\n\"nodes\": [1, 2,\n")); },
              {"a.json:", "not valid JSON"});
  const std::string good = CubitJsonText(Extract({CubicCurve()}));
  std::string bad = good;
  const std::string first = "\"coeff_vector_ids\": [ 0,";
  bad.replace(bad.find(first), first.size(), "\"coeff_vector_ids\": [ 999,");
  ExpectInputError([&] { fem::ReadCubitJson(dir.Write("b.json", bad)); },
              {"b.json", "elements.element_blocks[0]", "coefficient vector 999 out of range"});
  ExpectInputError([&] { fem::ReadCubitJson(dir.Write("c.json", "{\"control_points\": {}, \"elements\": {}}")); },
              {"c.json", "new Bezier extraction JSON format is not read"});
  // A number past the doubles made the JSON library throw past the reader
  // (found by fuzz_fem): an input error naming its line.
  ExpectInputError([&] { fem::ReadCubitJson(dir.Write("f.json", "{\"patch_id\": 0,\n\"nodes\": [[1e999, 0, 0, 1]]}")); },
                   {"f.json:2:", "a number out of the range of doubles"});
  EXPECT_FALSE(fem::LooksLikeCubitJson(dir.Write("d.json", "{\"format\": \"invmap-geometry\", \"version\": 1}")));
  EXPECT_TRUE(fem::LooksLikeCubitJson(dir.Write("e.json", " {\n  \"block_elem_map\": []}")));
}

TEST(CubitExtraction, BadExodusBexFilesNameTheBlock) {
  const ScratchDir dir;
  TestModel model = Extract({CubicCurve()});
  model.vectors[3].pop_back();
  ASSERT_TRUE(WriteExodusBex(dir.Path("short.exo"), model));
  ExpectInputError([&] { fem::ReadExodus(dir.Path("short.exo"), {}); },
              {"short.exo", "element block 1 (BEX_CURVE), element 0 of the block", "coefficient vector 3"});
}

}  // namespace
}  // namespace invmap::testing
