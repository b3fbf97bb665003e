// Tests of the JSON geometry reader (docs/formats.md section 2): every accepted
// form, every validation message with its JSON path and line (the reader's
// own, and Manifold::Build's mapped back to the file by GeometrySource),
// malformed and hostile files, and round trips through Manifold::Build.
#include "tests/io/io_scratch.h"
#include "io/geometry_json.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <sstream>
#include <string>

#include "invmap/invmap.h"
#include "io/geometry_file.h"
#include "io/input_error.h"

namespace invmap::io {
namespace {

/// A geometry document whose patches array holds `body`; body line k is
/// file line 5 + k, which the line checks below rely on.
std::string Doc(int dimension, const std::string& body) {
  return "{\n  \"format\": \"invmap-geometry\",\n  \"version\": 1,\n  \"dimension\": " + std::to_string(dimension) +
         ",\n  \"patches\": [\n" + body + "\n]}\n";
}

/// Reads `text` as the file g.json and validates it as the command does:
/// the reader's errors, then Manifold::Build's at the line of the value at
/// fault.
Geometry Parse(const std::string& text) {
  std::istringstream in(text);
  GeometrySource source;
  Geometry geometry = ReadGeometryJson(in, "g.json", &source);
  EXPECT_EQ(source.file(), "g.json");
  source.Check(Manifold::Build(geometry).problem);
  return geometry;
}

using invmap::io::scratch::ExpectInputError;

void ExpectParseError(const std::string& text, std::int64_t line, std::initializer_list<std::string> parts) {
  const std::string message = ExpectInputError([&] { Parse(text); }, line, parts);
  // The file name and line lead the message (input_error.h).
  EXPECT_EQ(message.rfind("g.json:" + std::to_string(line) + ": ", 0), 0u) << message;
}

/// A scratch directory for file-based tests, removed afterwards.
using TempDir = invmap::io::scratch::ScratchDir;

/// Closest point of one query through a built manifold.
struct Closest {
  Status status;
  std::int32_t patch;
  std::int64_t cell;
  double params[3];
  double point[3];
  double distance;
};

Closest Query(const Geometry& geometry, const double* query) {
  BuildResult built = Manifold::Build(geometry);
  EXPECT_TRUE(built.error.empty()) << built.error;
  Results results;
  std::string message;
  EXPECT_EQ(built.manifold.Invert(PointsView::Interleaved(query, 1, geometry.dimension), {}, &results, &message),
            Error::Ok)
      << message;
  Closest c{results.status[0], results.patch[0], results.cell[0], {}, {}, results.distance[0]};
  for (int k = 0; k < 3; ++k) {
    c.params[k] = results.params[k];
    c.point[k] = results.closest[k];
  }
  return c;
}

// ------------------------------------------------------------ accepted forms

TEST(GeometryJson, EmptyPatchListIsReadAndRefusedByTheBuild) {
  // The reader accepts the empty list (the format allows it); the build
  // refuses a geometry without cells, naming the file.
  std::istringstream in(Doc(2, ""));
  GeometrySource source;
  const Geometry g = ReadGeometryJson(in, "g.json", &source);
  EXPECT_EQ(g.dimension, 2);
  EXPECT_TRUE(g.patches.empty());
  ExpectInputError([&] { Parse(Doc(2, "")); }, 0, {"g.json: the geometry has no cells"});
}

TEST(GeometryJson, BSplineCurveSurfaceAndVolume) {
  const Geometry g = Parse(Doc(3, R"(
    {"kind": "bspline", "degrees": [2], "counts": [4], "knots": [[0, 0, 0, 0.5, 1, 1, 1]],
     "control_points": [[0, 0, 0], [1, 1, 0], [2, 1, 0], [3, 0, 0]], "weights": [1, 0.5, 2, 1]},
    {"kind": "bspline", "degrees": [1, 2], "counts": [2, 3],
     "knots": [[0, 0, 1, 1], [0, 0, 0, 1, 1, 1]],
     "control_points": [[0, 0, 0], [1, 0, 0], [0, 1, 1], [1, 1, 1], [0, 2, 0], [1, 2, 0]]},
    {"kind": "bspline", "degrees": [1, 1, 1], "counts": [2, 2, 2],
     "knots": [[0, 0, 1, 1], [0, 0, 1, 1], [-1, -1, 2, 2]],
     "control_points": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1], [1, 1, 1]]})"));
  ASSERT_EQ(g.patches.size(), 3u);
  const Patch& curve = g.patches[0];
  EXPECT_EQ(curve.kind, Patch::Kind::BSpline);
  EXPECT_EQ(curve.degrees, std::vector<int>({2}));
  EXPECT_EQ(curve.counts, std::vector<int>({4}));
  ASSERT_EQ(curve.knots.size(), 1u);
  EXPECT_EQ(curve.knots[0], std::vector<double>({0, 0, 0, 0.5, 1, 1, 1}));
  EXPECT_EQ(curve.points, std::vector<double>({0, 0, 0, 1, 1, 0, 2, 1, 0, 3, 0, 0}));
  EXPECT_EQ(curve.weights, std::vector<double>({1, 0.5, 2, 1}));
  EXPECT_EQ(g.patches[1].degrees, std::vector<int>({1, 2}));
  EXPECT_EQ(g.patches[1].points.size(), 18u);
  EXPECT_TRUE(g.patches[1].weights.empty());
  EXPECT_EQ(g.patches[2].knots[2], std::vector<double>({-1, -1, 2, 2}));
  EXPECT_TRUE(Manifold::Build(g).error.empty()) << Manifold::Build(g).error;
}

TEST(GeometryJson, BezierCellOfEveryType) {
  // Control point counts: line p+1, tri (p+1)(p+2)/2, quad (p+1)(q+1),
  // tet (p+1)(p+2)(p+3)/6, hex (p+1)(q+1)(r+1), wedge tri(p) x (q+1).
  const struct {
    const char* cell;
    const char* degrees;
    int points;
  } cases[] = {{"line", "[3]", 4}, {"tri", "[2]", 6},        {"quad", "[2, 1]", 6},
               {"tet", "[2]", 10}, {"hex", "[1, 1, 2]", 12}, {"wedge", "[1, 2]", 9}};
  const CellType types[] = {CellType::Line, CellType::Tri, CellType::Quad,
                            CellType::Tet,  CellType::Hex, CellType::Wedge};
  for (int c = 0; c < 6; ++c) {
    SCOPED_TRACE(cases[c].cell);
    std::string points, weights;
    for (int i = 0; i < cases[c].points; ++i) {
      points += std::string(i ? ", " : "") + "[" + std::to_string(i) + ", " + std::to_string(i * i) + ", " +
                std::to_string(i % 3) + "]";
      weights += std::string(i ? ", " : "") + "1.5";
    }
    const Geometry g = Parse(Doc(3, std::string("{\"kind\": \"bezier\", \"cell\": \"") + cases[c].cell +
                                        "\", \"degrees\": " + cases[c].degrees + ", \"control_points\": [" + points +
                                        "], \"weights\": [" + weights + "]}"));
    ASSERT_EQ(g.patches.size(), 1u);
    EXPECT_EQ(g.patches[0].kind, Patch::Kind::Bezier);
    EXPECT_EQ(g.patches[0].cell, types[c]);
    EXPECT_EQ(g.patches[0].points.size(), 3u * cases[c].points);
    EXPECT_EQ(g.patches[0].weights.size(), static_cast<std::size_t>(cases[c].points));
  }
}

TEST(GeometryJson, MeshOfEveryType) {
  const struct {
    const char* cell;
    CellType type;
    int vertices;
  } cases[] = {{"line", CellType::Line, 2}, {"tri", CellType::Tri, 3}, {"quad", CellType::Quad, 4},
               {"tet", CellType::Tet, 4},   {"hex", CellType::Hex, 8}, {"wedge", CellType::Wedge, 6}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.cell);
    std::string vertices, cell;
    for (int i = 0; i < c.vertices; ++i) {
      vertices += std::string(i ? ", " : "") + "[" + std::to_string(i) + ", 0, " + std::to_string(i % 2) + "]";
      cell += std::string(i ? ", " : "") + std::to_string(c.vertices - 1 - i);
    }
    const Geometry g = Parse(Doc(3, std::string("{\"kind\": \"mesh\", \"cell\": \"") + c.cell + "\", \"vertices\": [" +
                                        vertices + "], \"cells\": [[" + cell + "], [" + cell + "]]}"));
    ASSERT_EQ(g.patches.size(), 1u);
    EXPECT_EQ(g.patches[0].kind, Patch::Kind::Mesh);
    EXPECT_EQ(g.patches[0].cell, c.type);
    EXPECT_EQ(g.patches[0].cells.size(), 2u * c.vertices);
    EXPECT_EQ(g.patches[0].cells[0], c.vertices - 1);
  }
}

TEST(GeometryJson, FieldsInAnyOrderAndUnknownTopLevelFieldsIgnored) {
  // "dimension" after "patches", "kind" and "cell" after the data, integral
  // floats as indices, exponents, metadata of any shape at the top level.
  const Geometry g = Parse(R"({
    "patches": [{"cells": [[0, 1.0, 2e0]], "vertices": [[0, 0], [1E0, 0], [0, 1.0]], "cell": "tri", "kind": "mesh"}],
    "name": "triangle", "units": {"length": "mm", "list": [[1], {"a": null}]},
    "dimension": 2, "version": 1, "format": "invmap-geometry", "tags": [true, false, null]
  })");
  EXPECT_EQ(g.dimension, 2);
  ASSERT_EQ(g.patches.size(), 1u);
  EXPECT_EQ(g.patches[0].cells, std::vector<std::int64_t>({0, 1, 2}));
  EXPECT_EQ(g.patches[0].points, std::vector<double>({0, 0, 1, 0, 0, 1}));
}

TEST(GeometryJson, DimensionAfterPatchesIsCheckedAtTheEnd) {
  // Checks that need the dimension wait for it; they still name the point's line.
  const std::string patches =
      "{\"format\": \"invmap-geometry\", \"version\": 1, \"patches\": [\n"
      " {\"kind\": \"mesh\", \"cell\": \"tri\", \"vertices\": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], \"cells\": [[0, 1, "
      "2]]},\n"
      " {\"kind\": \"bezier\", \"cell\": \"line\", \"degrees\": [1], \"control_points\": [[0, 0],\n [1, 0]]},\n"
      " {\"kind\": \"bezier\",\n \"cell\": \"tet\", \"degrees\": [1], \"control_points\": [[0, 0], [1, 0], [0, 1], [1, "
      "1]]}],\n";
  ExpectParseError(patches + " \"dimension\": 3}", 3, {"patches[1].control_points[0]: 2 coordinates, expected 3"});
  ExpectParseError(patches + " \"dimension\": 2}", 2, {"patches[0].vertices[0]: 3 coordinates, expected 2"});
  ExpectParseError(patches + " \"dimension\": 3, \"dimension\": 3}", 7, {"duplicate field \"dimension\""});
}

TEST(GeometryJson, PathOverloadAndDispatchByExtension) {
  TempDir dir;
  const std::string text =
      Doc(3, R"({"kind": "bezier", "cell": "line", "degrees": [1], "control_points": [[0, 0, 0], [1, 2, 3]]})");
  const Geometry a = ReadGeometryJson(dir.Write("a.json", text));
  const Geometry b = ReadGeometryFile(dir.Write("b.JSON", text));
  ASSERT_EQ(a.patches.size(), 1u);
  ASSERT_EQ(b.patches.size(), 1u);
  EXPECT_EQ(a.patches[0].points, b.patches[0].points);
  EXPECT_EQ(b.patches[0].points, std::vector<double>({0, 0, 0, 1, 2, 3}));
}

TEST(GeometryJson, WindowsLineEndingsAndByteOrderMark) {
  std::string text =
      "\xEF\xBB\xBF" + Doc(2, R"({"kind": "mesh", "cell": "line", "vertices": [[0, 0], [1, 0]], "cells": [[0, 1]]})");
  std::string crlf;
  for (char c : text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  EXPECT_EQ(Parse(crlf).patches.size(), 1u);
  // Lines still count "\n": the bad index is on body line 2 = file line 7.
  std::string bad =
      Doc(2, "{\"kind\": \"mesh\", \"cell\": \"line\", \"vertices\": [[0, 0], [1, 0]],\r\n \"cells\": [[0, 2]]}");
  ExpectParseError(bad, 7, {"patches[0].cells[0]: vertex index 2 out of range (the patch has 2 vertices)"});
}

// ------------------------------------------------------------ JSON syntax

TEST(GeometryJson, SyntaxErrorsNameTheLine) {
  ExpectParseError(Doc(3, "{\"kind\": \"mesh\"\n \"cell\": \"tri\"}"), 7, {"invalid JSON", "syntax error"});
  ExpectParseError(Doc(3, "{\"kind\": \"mesh\",\n\n \"cell\": 'tri'}"), 8, {"invalid JSON"});
  ExpectParseError(Doc(3, "") + "\n\n{}", 10, {"invalid JSON", "end of input"});
}

TEST(GeometryJson, NanAndInfinityLiteralsAreRejected) {
  const std::string head =
      "{\"kind\": \"bezier\", \"cell\": \"line\", \"degrees\": [1],\n \"control_points\": [[0, 0, 0], [1, ";
  ExpectParseError(Doc(3, head + "NaN, 0]]}"), 7,
                   {"invalid JSON", "JSON has no NaN or infinity: every number must be finite"});
  ExpectParseError(Doc(3, head + "-Infinity, 0]]}"), 7,
                   {"invalid JSON", "JSON has no NaN or infinity: every number must be finite"});
  ExpectParseError(Doc(3, head + "nan, 0]]}"), 7, {"invalid JSON", "JSON has no NaN or infinity"});
  ExpectParseError(Doc(3, head + "inf, 0]]}"), 7, {"invalid JSON", "JSON has no NaN or infinity"});
  ExpectParseError(Doc(3, head + "1e400, 0]]}"), 7, {"invalid JSON", "overflow", "1e400"});
}

TEST(GeometryJson, EmptyTruncatedAndNonObjectFiles) {
  ExpectParseError("", 1, {"empty file"});
  ExpectParseError("  \n\t\n", 3, {"empty file"});
  const std::string full = Doc(3, R"({"kind": "bezier", "cell": "line", "degrees": [1],
 "control_points": [[0, 0, 0], [1, 2, 3]]})");
  // Cut at every length: always an InputError, never a crash or a geometry.
  for (std::size_t cut = 1; cut + 2 < full.size(); ++cut) {
    std::istringstream in(full.substr(0, cut));
    EXPECT_THROW(ReadGeometryJson(in, "g.json"), InputError) << "cut at " << cut;
  }
  ExpectParseError(full.substr(0, full.size() / 2), 6, {"unexpected end of input"});
  ExpectParseError("[1, 2]", 1, {"expected a JSON object at the top level, found an array"});
  ExpectParseError("3", 1, {"expected a JSON object at the top level, found 3"});
  ExpectParseError("{\"format\": \"invmap-geometry\"} x", 1, {"invalid JSON"});
}

TEST(GeometryJson, MissingFileAndDirectory) {
  TempDir dir;
  ExpectInputError([&] { ReadGeometryJson(dir.Path("missing.json")); }, 0, {"missing.json", "no such file"});
  ExpectInputError([&] { ReadGeometryJson(dir.Path("")); }, 0, {"directory"});
  ExpectInputError([&] { ReadGeometryFile(dir.Write("empty.json", "")); }, 1, {"empty.json:1: empty file"});
}

// ------------------------------------------------------------ top level

TEST(GeometryJson, TopLevelFieldErrors) {
  ExpectParseError("{\"format\": \"other\", \"version\": 1}", 1,
                   {"format: the string \"other\", expected \"invmap-geometry\""});
  ExpectParseError("{\n\"version\": 1, \"dimension\": 3, \"patches\": []}", 1, {"missing field \"format\""});
  ExpectParseError("{\"format\": \"invmap-geometry\",\n \"version\": 2}", 2,
                   {"version: 2, this reader supports version 1"});
  ExpectParseError("{\"format\": \"invmap-geometry\", \"version\": \"1\"}", 1,
                   {"version: expected an integer, found the string \"1\""});
  ExpectParseError("{\"format\": \"invmap-geometry\", \"version\": 1, \"patches\": []}", 1,
                   {"missing field \"dimension\""});
  ExpectParseError("{\"format\": \"invmap-geometry\", \"dimension\": 3, \"patches\": []}", 1,
                   {"missing field \"version\""});
  ExpectParseError("{\"format\": \"invmap-geometry\", \"version\": 1, \"dimension\": 3}", 1,
                   {"missing field \"patches\""});
  ExpectParseError("{\"format\": \"invmap-geometry\", \"version\": 1,\n\n \"dimension\": 4}", 3,
                   {"dimension: 4, expected 2 or 3"});
  ExpectParseError("{\"format\": \"invmap-geometry\", \"version\": 1, \"dimension\": 2.5}", 1,
                   {"dimension: expected an integer, found 2.5"});
  ExpectParseError("{\"format\": \"invmap-geometry\", \"dimension\": 3, \"dimension\": 3}", 1,
                   {"duplicate field \"dimension\""});
  ExpectParseError("{\"format\": \"invmap-geometry\", \"patches\": {}}", 1, {"patches: unexpected object"});
  ExpectParseError("{\"format\": \"invmap-geometry\", \"patches\": 7}", 1,
                   {"patches: expected an array of patch objects, found 7"});
  ExpectParseError(Doc(3, "{\"kind\": \"mesh\", \"cell\": \"line\", \"vertices\": [], \"cells\": []},\n 3"), 7,
                   {"patches[1]: expected a patch object, found 3"});
  ExpectParseError(Doc(3, "[]"), 6, {"patches[0]: expected a patch object, found an array"});
}

// ------------------------------------------------------------ patch fields

/// One invalid patch body, the line of the problem and the message parts.
struct BadPatch {
  const char* label;
  int dimension;
  const char* body;
  std::int64_t line;
  const char* message;
};

class GeometryJsonBadPatch : public ::testing::TestWithParam<BadPatch> {};

TEST_P(GeometryJsonBadPatch, NamesPatchFieldAndLine) {
  const BadPatch& c = GetParam();
  ExpectParseError(Doc(c.dimension, c.body), c.line, {c.message});
}

// Body line k is file line 5 + k.
const BadPatch kBadPatches[] = {
    {"UnknownKind", 3, R"({"kind": "nurbs", "degrees": [1]})", 6,
     "patches[0].kind: unknown patch kind \"nurbs\" (expected bspline, bezier, mesh or pou_manifold)"},
    {"MissingKind", 3, "{\"cell\": \"tri\",\n \"vertices\": []}", 6,
     "patches[0]: missing field \"kind\" (bspline, bezier, mesh or pou_manifold)"},
    {"KindNotString", 3, R"({"kind": 3})", 6, "patches[0].kind: expected a string (bspline, bezier, mesh or pou_manifold), found 3"},
    {"PouChartPointRow", 3,
     "{\"kind\": \"pou_manifold\", \"vertices\": [], \"cells\": [], \"degrees\": [],\n"
     " \"chart_control_points\": [[0, 0, 0], [1, 2]]}",
     7, "patches[0].chart_control_points[1]: 2 coordinates, expected 3"},
    {"PouInTwoDimensions", 2,
     R"({"kind": "pou_manifold", "vertices": [], "cells": [], "degrees": [], "chart_control_points": []})", 6,
     "patches[0].kind: a pou_manifold is a surface of R^3 (dimension 3), the file's dimension is 2"},
    {"UnknownCellType", 3, "{\"kind\": \"mesh\",\n \"cell\": \"pyramid\", \"vertices\": [], \"cells\": []}", 7,
     "patches[0].cell: unknown cell type \"pyramid\" (expected line, tri, quad, tet, hex or wedge)"},
    {"UnknownField", 3, "{\"kind\": \"bspline\",\n \"weight\": [1]}", 7, "patches[0]: unknown field \"weight\""},
    {"DuplicateField", 3, "{\"kind\": \"bspline\", \"kind\": \"mesh\"}", 6, "patches[0]: duplicate field \"kind\""},
    {"FieldOfAnotherKind", 3,
     "{\"kind\": \"bspline\", \"degrees\": [1], \"counts\": [2], \"knots\": [[0, 0, 1, 1]],\n \"cell\": \"line\",\n "
     "\"control_points\": [[0, 0, 0], [1, 0, 0]]}",
     7, "patches[0]: field \"cell\" does not belong to a bspline patch"},
    {"WeightsOnMesh", 3,
     "{\"kind\": \"mesh\", \"cell\": \"line\", \"vertices\": [[0, 0, 0], [1, 0, 0]], \"cells\": [[0, 1]],\n "
     "\"weights\": [1, 1]}",
     7, "patches[0]: field \"weights\" does not belong to a mesh patch"},
    {"MissingRequired", 3, "{\"kind\": \"mesh\", \"cell\": \"tri\",\n \"vertices\": [[0, 0, 0]]}", 6,
     "patches[0]: missing field \"cells\" (required for a mesh patch)"},
    {"EmptyPatchObject", 3, "{},\n{\"kind\": \"bezier\", \"cell\": \"line\", \"control_points\": []}", 6,
     "patches[0]: missing field \"kind\""},
    {"SecondPatchMissingDegrees", 3,
     "{\"kind\": \"mesh\", \"cell\": \"line\", \"vertices\": [], \"cells\": []},\n"
     "{\"kind\": \"bezier\", \"cell\": \"line\", \"control_points\": []}",
     7, "patches[1]: missing field \"degrees\" (required for a bezier patch)"},
    // Points.
    {"TooFewCoordinates", 3,
     "{\"kind\": \"mesh\", \"cell\": \"tri\", \"vertices\": [\n  [0, 0, 0],\n  [1, 0],\n  [0, 1, 0]], \"cells\": [[0, "
     "1, "
     "2]]}",
     8, "patches[0].vertices[1]: 2 coordinates, expected 3 (the dimension)"},
    {"FirstPointWrongForDimension", 2,
     R"({"kind": "bezier", "cell": "line", "degrees": [1], "control_points": [[0, 0, 0], [1, 0, 0]]})", 6,
     "patches[0].control_points[0]: 3 coordinates, expected 2 (the dimension)"},
    {"NullCoordinate", 3,
     "{\"kind\": \"bezier\", \"cell\": \"line\", \"degrees\": [1],\n \"control_points\": [[0, 0, 0], [1, null, 0]]}", 7,
     "patches[0].control_points[1][1]: expected a number, found null"},
    {"StringCoordinate", 3,
     "{\"kind\": \"bezier\", \"cell\": \"line\", \"degrees\": [1],\n \"control_points\": [[0, 0, 0], [1, \"NaN\", 0]]}",
     7, "patches[0].control_points[1][1]: expected a number, found the string \"NaN\""},
    {"BooleanCoordinate", 3,
     "{\"kind\": \"bezier\", \"cell\": \"line\", \"degrees\": [1],\n \"control_points\": [[0, 0, 0], [1, 1, true]]}", 7,
     "patches[0].control_points[1][2]: expected a number, found true"},
    {"PointNotArray", 3,
     "{\"kind\": \"bezier\", \"cell\": \"line\", \"degrees\": [1],\n \"control_points\": [0, 0, 0]}", 7,
     "patches[0].control_points[0]: expected a point (array of numbers), found 0"},
    {"NestedTooDeep", 3,
     "{\"kind\": \"bezier\", \"cell\": \"line\", \"degrees\": [1],\n \"control_points\": [[[0, 0, 0]]]}", 7,
     "patches[0].control_points[0][0]: expected a number, found an array"},
    {"ObjectAsPoint", 3,
     "{\"kind\": \"bezier\", \"cell\": \"line\", \"degrees\": [1],\n \"control_points\": [{\"x\": 0}]}", 7,
     "patches[0].control_points[0]: expected an array, found an object"},
    {"FieldNotArray", 3, "{\"kind\": \"bspline\",\n \"knots\": 5}", 7,
     "patches[0].knots: expected an array of knot vectors (arrays of numbers), found 5"},
    // B-splines.
    {"KnotsDecreasing", 3,
     "{\"kind\": \"mesh\", \"cell\": \"line\", \"vertices\": [[0, 0, 0], [1, 0, 0]], \"cells\": [[0, 1]]},\n"
     "{\"kind\": \"bspline\", \"degrees\": [1, 1], \"counts\": [2, 4],\n"
     " \"knots\": [[0, 0, 1, 1],\n"
     "           [0, 0, 0.1, 0.5, 0.25, 1]], \"control_points\": []}",
     9, "patches[1].knots[1]: decreasing at index 4 (0.5 > 0.25)"},
    {"KnotsDecreasingOnAWrappedLine", 3,
     "{\"kind\": \"bspline\", \"degrees\": [1], \"counts\": [4], \"knots\": [[0, 0,\n    0.5,\n    0.25, 1, 1]],\n"
     " \"control_points\": [[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]]}",
     8, "patches[0].knots[0]: decreasing at index 3 (0.5 > 0.25)"},
    {"HugeCoordinateOnAWrappedLine", 2,
     "{\"kind\": \"bezier\", \"cell\": \"line\", \"degrees\": [1],\n \"control_points\": [[0, 0], [1,\n 2e100]]}",
     8, "patches[0].control_points[1]: coordinate 1 is 2e+100, outside [-1e100, 1e100] (the range invmap supports)"},
    {"KnotsDecreasingShortestDigits", 3,
     "{\"kind\": \"bspline\", \"degrees\": [1], \"counts\": [2],\n \"knots\": [[0.3, 0.1, 1, 1]],"
     " \"control_points\": []}",
     7,
     "patches[0].knots[0]: decreasing at index 1 (0.3 > 0.1)"},
    {"KnotVectorLength", 3,
     "{\"kind\": \"bspline\", \"degrees\": [1], \"counts\": [3],\n \"knots\": [\n  [0, 0, 0.5, 1]],\n"
     " \"control_points\": [[0, 0, 0], [1, 0, 0], [2, 0, 0]]}",
     8, "patches[0].knots[0]: length 4, expected counts[0] + degrees[0] + 1 = 5"},
    {"KnotVectorCount", 3,
     "{\"kind\": \"bspline\", \"degrees\": [1, 1], \"counts\": [2, 2],\n \"knots\": [[0, 0, 1, 1]],\n"
     " \"control_points\": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]}",
     7, "patches[0].knots: 1 knot vectors, expected one per degree (2)"},
    {"EmptyParameterDomain", 3,
     "{\"kind\": \"bspline\", \"degrees\": [1], \"counts\": [2],\n \"knots\": [[1, 1, 1, 1]],\n"
     " \"control_points\": [[0, 0, 0], [1, 0, 0]]}",
     7, "patches[0].knots[0]: empty parameter domain"},
    {"CountsBelowDegree", 3,
     "{\"kind\": \"bspline\", \"degrees\": [3],\n \"counts\": [2], \"knots\": [[0, 0, 0, 0, 1, 1]],\n"
     " \"control_points\": [[0, 0, 0], [1, 0, 0]]}",
     7, "patches[0].counts[0]: 2, expected at least degrees[0] + 1 = 4"},
    {"CountsPerDegree", 3,
     "{\"kind\": \"bspline\", \"degrees\": [1],\n \"counts\": [2, 2], \"knots\": [[0, 0, 1, 1]],\n"
     " \"control_points\": [[0, 0, 0], [1, 0, 0]]}",
     7, "patches[0].counts: 2 values, expected one per degree (1)"},
    {"ControlPointCount", 3,
     "{\"kind\": \"bspline\", \"degrees\": [1, 1], \"counts\": [2, 2], \"knots\": [[0, 0, 1, 1], [0, 0, 1, 1]],\n"
     " \"control_points\": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]}",
     7, "patches[0].control_points: 3 points, expected 4 (counts 2 x 2)"},
    {"ZeroDegree", 3,
     "{\"kind\": \"bspline\",\n \"degrees\": [0], \"counts\": [2], \"knots\": [[0, 0, 1, 1]],\n"
     " \"control_points\": [[0, 0, 0], [1, 0, 0]]}",
     7, "patches[0].degrees[0]: 0, expected 1 to 8"},
    {"DegreeAboveTheCap", 3, "{\"kind\": \"bezier\", \"cell\": \"tri\",\n \"degrees\": [9], \"control_points\": []}", 7,
     "patches[0].degrees[0]: 9, expected 1 to 8 (the highest degree invmap supports)"},
    {"CountOutOfIntRange", 3, "{\"kind\": \"bspline\", \"degrees\": [1],\n \"counts\": [3000000000]}", 7,
     "patches[0].counts[0]: 3000000000, expected an integer within [-2147483648, 2147483647]"},
    {"FractionalCount", 3, "{\"kind\": \"bspline\", \"degrees\": [1],\n \"counts\": [2.5]}", 7,
     "patches[0].counts[0]: expected an integer, found 2.5"},
    {"DegreeArray", 3, "{\"kind\": \"bspline\",\n \"degrees\": [[1]]}", 7,
     "patches[0].degrees[0]: expected an integer, found an array"},
    {"TooManyDegrees", 3,
     "{\"kind\": \"bspline\",\n \"degrees\": [1, 1, 1, 1], \"counts\": [], \"knots\": [],\n"
     " \"control_points\": []}",
     7, "patches[0].degrees: 4 values, expected 1 to 3 (one per parametric direction)"},
    {"VolumeIn2D", 2,
     "{\"kind\": \"bspline\",\n \"degrees\": [1, 1, 1], \"counts\": [2, 2, 2], \"knots\": [[0, 0, 1, 1], [0, 0, 1, 1], "
     "[0, 0, 1, 1]], \"control_points\": []}",
     7, "patches[0].degrees: a 3-parameter patch needs dimension 3"},
    // Weights.
    {"ZeroWeight", 2,
     "{\"kind\": \"bspline\", \"degrees\": [1], \"counts\": [2], \"knots\": [[0, 0, 1, 1]],\n"
     " \"control_points\": [[0, 0], [1, 0]],\n \"weights\": [1, 0]}",
     8, "patches[0].weights[1]: 0 is not positive"},
    {"HugeWeight", 2,
     "{\"kind\": \"bezier\", \"cell\": \"line\", \"degrees\": [1], \"control_points\": [[0, 0], [1, 0]],\n"
     " \"weights\": [1,\n 1e300]}",
     8, "patches[0].weights[1]: 1e+300 is outside [1e-50, 1e50] (the range invmap supports)"},
    {"HugeCoordinate", 2,
     "{\"kind\": \"bezier\", \"cell\": \"line\", \"degrees\": [1],\n \"control_points\": [[0, 0],\n [-1e101, 0]]}",
     8, "patches[0].control_points[1]: coordinate 0 is -1e+101, outside [-1e100, 1e100] (the range invmap supports)"},
    {"NegativeWeight", 2,
     "{\"kind\": \"bezier\", \"cell\": \"line\", \"degrees\": [1], \"control_points\": [[0, 0], [1, 0]],\n"
     " \"weights\": [-0.5, 1]}",
     7, "patches[0].weights[0]: -0.5 is not positive"},
    {"NullWeight", 2,
     "{\"kind\": \"bezier\", \"cell\": \"line\", \"degrees\": [1], \"control_points\": [[0, 0], [1, 0]],\n"
     " \"weights\": [null, 1]}",
     7, "patches[0].weights[0]: expected a number, found null"},
    {"WeightCount", 2,
     "{\"kind\": \"bezier\", \"cell\": \"line\", \"degrees\": [2], \"control_points\": [[0, 0], [1, 0], [2, 0]],\n"
     " \"weights\": [1, 1]}",
     7, "patches[0].weights: 2 values, expected one per control point (3)"},
    // Bezier cells.
    {"BezierDegreeCount", 3, "{\"kind\": \"bezier\", \"cell\": \"quad\",\n \"degrees\": [2], \"control_points\": []}",
     7, "patches[0].degrees: 1 values, a quad cell needs 2 [p, q]"},
    {"BezierPointCount", 3,
     "{\"kind\": \"bezier\", \"cell\": \"tri\", \"degrees\": [2],\n \"control_points\": [[0, 0, 0], [1, 0, 0], [2, 0, "
     "0], [0, 1, 0], [1, 1, 0]]}",
     7, "patches[0].control_points: 5 points, expected 6 for a tri cell of degrees [2]"},
    {"AbsurdBezierDegree", 3,
     "{\"kind\": \"bezier\", \"cell\": \"hex\", \"degrees\": [2000000000, 2000000000, 2000000000],\n"
     " \"control_points\": [[0, 0, 0]]}",
     6, "patches[0].degrees[0]: 2000000000, expected 1 to 8"},
    {"TetCellIn2D", 2, "{\"kind\": \"bezier\",\n \"cell\": \"tet\", \"degrees\": [1], \"control_points\": []}", 7,
     "patches[0].cell: a tet cell needs dimension 3"},
    // Meshes.
    {"CellVertexCount", 3,
     "{\"kind\": \"mesh\", \"cell\": \"tri\", \"vertices\": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]],\n"
     " \"cells\": [[0, 1, 2],\n  [0, 1, 2, 3]]}",
     8, "patches[0].cells[1]: 4 vertex indices, a tri cell has 3"},
    {"FirstCellVertexCount", 3,
     "{\"kind\": \"mesh\", \"cell\": \"hex\", \"vertices\": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]],\n"
     " \"cells\": [[0, 1, 2, 3]]}",
     7, "patches[0].cells[0]: 4 vertex indices, a hex cell has 8"},
    {"IndexOutOfRange", 3,
     "{\"kind\": \"mesh\", \"cell\": \"tri\",\n \"cells\": [[0, 1, 2],\n  [2, 1, 3]],\n"
     " \"vertices\": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]}",
     8, "patches[0].cells[1]: vertex index 3 out of range (the patch has 3 vertices)"},
    {"NegativeIndex", 3,
     "{\"kind\": \"mesh\", \"cell\": \"tri\", \"vertices\": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],\n"
     " \"cells\": [[0, 1, 2], [0, -1, 2]]}",
     7, "patches[0].cells[1]: vertex index -1 is negative"},
    {"FractionalIndex", 3,
     "{\"kind\": \"mesh\", \"cell\": \"tri\", \"vertices\": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],\n"
     " \"cells\": [[0, 1.5, 2]]}",
     7, "patches[0].cells[0][1]: expected a vertex index (integer), found 1.5"},
    {"HugeIndex", 3,
     "{\"kind\": \"mesh\", \"cell\": \"line\", \"vertices\": [[0, 0, 0], [1, 0, 0]],\n"
     " \"cells\": [[0, 18446744073709551615]]}",
     7, "patches[0].cells[0][1]: expected a vertex index (integer), found 18446744073709551615"},
    {"TetMeshIn2D", 2,
     "{\"kind\": \"mesh\",\n \"cell\": \"tet\", \"vertices\": [[0, 0], [1, 0], [0, 1], [1, 1]], \"cells\": [[0, 1, 2, "
     "3]]}",
     7, "patches[0].cell: a tet mesh needs dimension 3"},
};

INSTANTIATE_TEST_SUITE_P(All, GeometryJsonBadPatch, ::testing::ValuesIn(kBadPatches),
                         [](const ::testing::TestParamInfo<BadPatch>& param) {
                           return std::string(param.param.label);
                         });

// ------------------------------------------------------------ round trips

TEST(GeometryJson, RoundTripUnitSquareQuadMesh) {
  const Geometry g = Parse(Doc(3, R"({"kind": "mesh", "cell": "quad",
      "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], "cells": [[0, 1, 2, 3]]})"));
  const double query[3] = {0.3, 0.4, 2.0};
  const Closest c = Query(g, query);
  ASSERT_EQ(c.status, Status::Found);
  EXPECT_EQ(c.patch, 0);
  EXPECT_EQ(c.cell, 0);
  EXPECT_NEAR(c.point[0], 0.3, 1e-12);
  EXPECT_NEAR(c.point[1], 0.4, 1e-12);
  EXPECT_NEAR(c.point[2], 0.0, 1e-12);
  EXPECT_NEAR(c.distance, 2.0, 1e-12);
  // Quad vertex order (0,0) (1,0) (1,1) (0,1): parameters are (x, y).
  EXPECT_NEAR(c.params[0], 0.3, 1e-12);
  EXPECT_NEAR(c.params[1], 0.4, 1e-12);
}

TEST(GeometryJson, RoundTripRationalQuarterCircle) {
  // The exact NURBS quarter circle of radius 1: the closest point of (2, 2)
  // is (1/sqrt2, 1/sqrt2) at distance 2 sqrt2 - 1.
  const Geometry g = Parse(Doc(2, R"({"kind": "bspline", "degrees": [2], "counts": [3],
      "knots": [[0, 0, 0, 1, 1, 1]], "control_points": [[1, 0], [1, 1], [0, 1]],
      "weights": [1, 0.70710678118654752, 1]})"));
  const double query[2] = {2.0, 2.0};
  const Closest c = Query(g, query);
  ASSERT_EQ(c.status, Status::Found);
  EXPECT_NEAR(c.point[0], std::sqrt(0.5), 1e-10);
  EXPECT_NEAR(c.point[1], std::sqrt(0.5), 1e-10);
  EXPECT_NEAR(c.distance, 2 * std::sqrt(2.0) - 1, 1e-10);
  EXPECT_NEAR(c.params[0], 0.5, 1e-8);  // symmetric weights: the midpoint
}

TEST(GeometryJson, RoundTripBezierTriangleAndSecondPatch) {
  // A flat quadratic triangle over the unit right triangle at z = 1, then a
  // line segment far away: the query above the triangle finds patch 0.
  const Geometry g = Parse(Doc(3, R"({"kind": "bezier", "cell": "tri", "degrees": [2],
      "control_points": [[0, 0, 1], [0.5, 0, 1], [1, 0, 1], [0, 0.5, 1], [0.5, 0.5, 1], [0, 1, 1]]},
    {"kind": "mesh", "cell": "line", "vertices": [[10, 10, 10], [11, 10, 10]], "cells": [[0, 1]]})"));
  const double query[3] = {0.2, 0.3, -1.0};
  const Closest c = Query(g, query);
  ASSERT_EQ(c.status, Status::Found);
  EXPECT_EQ(c.patch, 0);
  EXPECT_NEAR(c.point[0], 0.2, 1e-10);
  EXPECT_NEAR(c.point[1], 0.3, 1e-10);
  EXPECT_NEAR(c.point[2], 1.0, 1e-10);
  EXPECT_NEAR(c.distance, 2.0, 1e-10);
  const double far[3] = {10.5, 10, 12};
  const Closest d = Query(g, far);
  EXPECT_EQ(d.patch, 1);
  EXPECT_NEAR(d.distance, 2.0, 1e-10);
  EXPECT_NEAR(d.params[0], 0.5, 1e-10);
}

}  // namespace
}  // namespace invmap::io
