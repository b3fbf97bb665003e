// Tests of the OBJ, STL and OFF mesh readers and of ReadGeometryFile's
// dispatch: every accepted form, every error with its line, hostile files
// (truncated, absurd counts, non-numbers), and round trips through
// Manifold::Build.
#include "tests/io/io_scratch.h"
#include "io/mesh_readers.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <random>
#include <streambuf>
#include <sstream>
#include <string>
#include <vector>

#include "invmap/invmap.h"
#include "io/file_io.h"
#include "io/geometry_file.h"
#include "io/input_error.h"

namespace invmap::io {
namespace {

Geometry Obj(const std::string& text) {
  std::istringstream in(text);
  return ReadObj(in, "m.obj");
}
Geometry Stl(const std::string& bytes) {
  std::istringstream in(bytes);
  return ReadStl(in, "m.stl");
}
Geometry Off(const std::string& text) {
  std::istringstream in(text);
  return ReadOff(in, "m.off");
}

using invmap::io::scratch::ExpectInputError;

/// A scratch directory for file-based tests, removed afterwards.
using TempDir = invmap::io::scratch::ScratchDir;

/// A binary STL: 80-byte header, little-endian triangle count, then per
/// triangle a normal, three corners (float32 LE) and two attribute bytes.
/// `claimedCount` overrides the count field when not negative.
std::string BinaryStl(const std::vector<std::array<float, 9>>& triangles, const std::string& header = "binary",
                      std::int64_t claimedCount = -1) {
  std::string bytes(80, '\0');
  std::memcpy(bytes.data(), header.data(), std::min<std::size_t>(header.size(), 80));
  const std::uint32_t count =
      claimedCount >= 0 ? static_cast<std::uint32_t>(claimedCount) : static_cast<std::uint32_t>(triangles.size());
  for (int b = 0; b < 4; ++b) bytes += static_cast<char>((count >> (8 * b)) & 0xff);
  const auto putFloat = [&](float x) {
    std::uint32_t bits;
    std::memcpy(&bits, &x, 4);
    for (int b = 0; b < 4; ++b) bytes += static_cast<char>((bits >> (8 * b)) & 0xff);
  };
  for (const auto& t : triangles) {
    for (int k = 0; k < 3; ++k) putFloat(0.0f);
    for (float x : t) putFloat(x);
    bytes += std::string(2, '\0');
  }
  return bytes;
}

/// Closest point of one 3D query through a built manifold.
struct Closest {
  Status status;
  std::int32_t patch;
  std::int64_t cell;
  double point[3];
  double distance;
};

Closest Query(const Geometry& geometry, double x, double y, double z) {
  BuildResult built = Manifold::Build(geometry);
  EXPECT_TRUE(built.error.empty()) << built.error;
  const double query[3] = {x, y, z};
  Results results;
  EXPECT_EQ(built.manifold.Invert(PointsView::Interleaved(query, 1, 3), {}, &results), Error::Ok);
  return {results.status[0],
          results.patch[0],
          results.cell[0],
          {results.closest[0], results.closest[1], results.closest[2]},
          results.distance[0]};
}

// ------------------------------------------------------------ OBJ

TEST(ObjReader, EveryFaceFormRelativeIndicesAndPolygons) {
  const Geometry g =
      Obj("# a comment\n"
          "mtllib m.mtl\n"
          "o thing\n"
          "v 0 0 0\n"
          "v 1 0 0 1.0\n"          // w is ignored
          "v 1 1 0 0.5 0.5 0.5\n"  // so are vertex colours
          "v 0 1 0\n"
          "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n"
          "g group\ns off\nusemtl red\n"
          "f 1 2 3\n"                               // v
          "f 1/1 3/3 4/1\n"                         // v/vt
          "f 1/1/1 2/2/1 3/3/1 4/1/1\n"             // v/vt/vn: a quad
          "f 1//1 2//1 4//1  # trailing comment\n"  // v//vn
          "f -4 -3 -2\n"                            // relative: vertices 1 2 3
          "v 2 0 0\nv 2 1 0\n"
          "f 2 5 6 3 4 1\n"  // hexagon: fan of 4 triangles
          "l 1 2\np 1\n");
  EXPECT_EQ(g.dimension, 3);
  ASSERT_EQ(g.patches.size(), 2u);
  const Patch& tris = g.patches[0];
  const Patch& quads = g.patches[1];
  EXPECT_EQ(tris.kind, Patch::Kind::Mesh);
  EXPECT_EQ(tris.cell, CellType::Tri);
  EXPECT_EQ(quads.cell, CellType::Quad);
  EXPECT_EQ(tris.points, std::vector<double>({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 2, 0, 0, 2, 1, 0}));
  EXPECT_EQ(quads.points, tris.points);
  EXPECT_EQ(tris.cells, std::vector<std::int64_t>({0, 1, 2, 0, 2, 3, 0, 1, 3, 0, 1, 2,     // tri faces in order
                                                   1, 4, 5, 1, 5, 2, 1, 2, 3, 1, 3, 0}));  // the fan
  EXPECT_EQ(quads.cells, std::vector<std::int64_t>({0, 1, 2, 3}));
}

TEST(ObjReader, QuadsOnlyGiveOneQuadPatchAndCrLfIsAccepted) {
  const Geometry g = Obj("v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\nf 1 2 3 4\r\n");
  ASSERT_EQ(g.patches.size(), 1u);
  EXPECT_EQ(g.patches[0].cell, CellType::Quad);
}

TEST(ObjReader, FacesMayReferToVerticesDefinedLater) {
  const Geometry g = Obj("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
  ASSERT_EQ(g.patches.size(), 1u);
  EXPECT_EQ(g.patches[0].cells, std::vector<std::int64_t>({0, 1, 2}));
}

TEST(ObjReader, Errors) {
  const std::string v3 = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  ExpectInputError([&] { Obj(v3 + "v 1 2\n"); }, 4, {"m.obj:4: v: 2 coordinates, expected 3"});
  ExpectInputError([&] { Obj(v3 + "v 1 abc 2\n"); }, 4, {"v: coordinate 1: \"abc\" is not a number"});
  ExpectInputError([&] { Obj(v3 + "v 1 nan 2\n"); }, 4, {"v: coordinate 1: \"nan\" is not a finite number"});
  ExpectInputError([&] { Obj(v3 + "v inf 0 2\n"); }, 4, {"v: coordinate 0: \"inf\" is not a finite number"});
  ExpectInputError([&] { Obj(v3 + "v 1e999 0 2\n"); }, 4, {"is not a finite number"});
  ExpectInputError([&] { Obj(v3 + "\nf 1 2 4\n"); }, 5, {"f: vertex index 4 out of range (the file has 3 vertices)"});
  ExpectInputError([&] { Obj(v3 + "f 0 1 2\n"); }, 4, {"f: vertex index 0 (OBJ indices start at 1)"});
  ExpectInputError([&] { Obj(v3 + "f -1 -2 -4\n"); }, 4,
                   {"f: relative vertex index -4 refers before the first vertex (3 defined so far)"});
  ExpectInputError([&] { Obj(v3 + "f 1 2 x/1\n"); }, 4, {"f: \"x/1\" is not a vertex reference"});
  ExpectInputError([&] { Obj(v3 + "f 1 //2 3\n"); }, 4, {"f: \"//2\" is not a vertex reference"});
  ExpectInputError([&] { Obj(v3 + "f 1 2\n"); }, 4, {"f: 2 vertices, a face needs at least 3"});
  ExpectInputError([&] { Obj(v3 + "f 1 2 99999999999999999999\n"); }, 4, {"is not a vertex reference"});
  ExpectInputError([&] { Obj(v3 + "f 1 2 -9223372036854775808\n"); }, 4, {"refers before the first vertex"});
  ExpectInputError([&] { Obj(v3); }, 3, {"no faces"});
  ExpectInputError([&] { Obj(""); }, 1, {"m.obj:1: no faces"});
}

// ------------------------------------------------------------ STL

const std::vector<std::array<float, 9>> kTwoTriangles = {
    {0, 0, 0, 1, 0, 0, 1, 1, 0}, {0, 0, 0, 1, 1, 0, 0, 1, -0.0f},  // -0 merges with 0
};

TEST(StlReader, BinaryMergesIdenticalVertices) {
  const Geometry g = Stl(BinaryStl(kTwoTriangles));
  ASSERT_EQ(g.patches.size(), 1u);
  const Patch& p = g.patches[0];
  EXPECT_EQ(p.cell, CellType::Tri);
  EXPECT_EQ(p.points, std::vector<double>({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}));
  EXPECT_EQ(p.cells, std::vector<std::int64_t>({0, 1, 2, 0, 2, 3}));
}

TEST(StlReader, BinaryDetectedBySizeEvenWithSolidHeader) {
  const Geometry g = Stl(BinaryStl(kTwoTriangles, "solid looks like ascii"));
  ASSERT_EQ(g.patches.size(), 1u);
  EXPECT_EQ(g.patches[0].cells.size(), 6u);
}

TEST(StlReader, Ascii) {
  const Geometry g =
      Stl("solid two triangles\n"
          "  facet normal 0 0 1\n"
          "    outer loop\n"
          "      vertex 0 0 0\n"
          "      vertex 1 0 0\n"
          "      vertex 1 1 0\n"
          "    endloop\n"
          "  endfacet\n"
          "  facet normal nan nan nan\n"  // degenerate-normal writers
          "    outer loop\n"
          "      vertex 0 0 0\n      vertex +1 1e0 0\n      vertex 0 1 -0\n"
          "    endloop\n"
          "  endfacet\n"
          "endsolid two triangles\n"
          "SOLID second\n FACET NORMAL 0 0 1 OUTER LOOP VERTEX 5 5 5 VERTEX 6 5 5 VERTEX 5 6 5 ENDLOOP ENDFACET\n"
          "ENDSOLID\n");
  ASSERT_EQ(g.patches.size(), 1u);
  EXPECT_EQ(g.patches[0].points, std::vector<double>({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 5, 5, 5, 6, 5, 5, 5, 6, 5}));
  EXPECT_EQ(g.patches[0].cells, std::vector<std::int64_t>({0, 1, 2, 0, 2, 3, 4, 5, 6}));
}

TEST(StlReader, BinaryErrors) {
  // A count of 4 G triangles in a 100-byte file: refused before allocating.
  std::string huge = BinaryStl({}, "binary", 0xffffffffll);
  huge.resize(100, '\0');
  ExpectInputError([&] { Stl(huge); }, 0,
                   {"m.stl: not an STL file", "4294967295 triangles", "= 214748364834 bytes", "this file has 100"});
  // Truncated: one byte short.
  std::string cut = BinaryStl(kTwoTriangles);
  cut.pop_back();
  ExpectInputError([&] { Stl(cut); }, 0, {"not an STL file", "2 triangles", "184 bytes, this file has 183"});
  // The same with a "solid" header: binary data, not ASCII.
  std::string cutSolid = BinaryStl(kTwoTriangles, "solid x");
  cutSolid.pop_back();
  ExpectInputError([&] { Stl(cutSolid); }, 0, {"binary data after a \"solid\" header", "this file has 183"});
  ExpectInputError([&] { Stl(std::string(50, 'x')); }, 0, {"50 bytes is too short for a binary STL"});
  ExpectInputError([&] { Stl(""); }, 0, {"0 bytes is too short"});
  ExpectInputError([&] { Stl(BinaryStl({})); }, 0, {"no faces"});
  const float nan = std::nanf("");
  ExpectInputError(
      [&] {
        Stl(BinaryStl({kTwoTriangles[0], {0, 0, 0, 1, 0, 0, 1, nan, 0}}));
      },
      0, {"triangle 1, vertex 2: coordinate is not a finite number"});
  const float inf = INFINITY;
  ExpectInputError([&] { Stl(BinaryStl({{inf, 0, 0, 1, 0, 0, 1, 1, 0}})); }, 0, {"triangle 0, vertex 0"});
}

TEST(StlReader, AsciiErrors) {
  const std::string head = "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n";
  ExpectInputError([&] { Stl(head + "vertex 1 x 0\nendloop\nendfacet\nendsolid\n"); }, 6,
                   {"m.stl:6: vertex: coordinate 1: \"x\" is not a number"});
  ExpectInputError([&] { Stl(head + "vertex 1 nan 0\nendloop\nendfacet\nendsolid\n"); }, 6, {"is not a finite number"});
  // A vertex line short of a coordinate is blamed, not the next line's keyword.
  ExpectInputError([&] { Stl(head + "vertex 1 0\nendloop\nendfacet\nendsolid\n"); }, 6,
                   {"m.stl:6: vertex: 2 coordinates, expected 3"});
  ExpectInputError([&] { Stl(head + "vertex\nendloop\nendfacet\nendsolid\n"); }, 6, {"vertex: 0 coordinates"});
  ExpectInputError([&] { Stl(head + "vertex 1 1 0\nendfacet\n"); }, 7,
                   {"unexpected \"endfacet\", expected \"endloop\""});
  ExpectInputError([&] { Stl(head + "vertex 1 1 0\nvertex 2 2 2\n"); }, 7,
                   {"unexpected \"vertex\", expected \"endloop\""});
  ExpectInputError([&] { Stl(head); }, 5, {"unexpected end of file, expected \"vertex\""});
  ExpectInputError([&] { Stl(head + "vertex 1 1"); }, 6, {"unexpected end of file, expected a vertex coordinate"});
  ExpectInputError([&] { Stl(head + "vertex 1 1 0\nendloop\nendfacet\n"); }, 8,
                   {"unexpected end of file, expected \"facet\" or \"endsolid\""});
  ExpectInputError([&] { Stl("solid s\n\nfoo\n"); }, 3, {"unexpected \"foo\", expected \"facet\" or \"endsolid\""});
  ExpectInputError([&] { Stl("solid s\nendsolid s\nbar\n"); }, 3, {"unexpected \"bar\" after \"endsolid\""});
  ExpectInputError([&] { Stl("solid s\nendsolid s\n"); }, 2, {"no faces"});
  ExpectInputError([&] { Stl("hello world, this is not an stl file at all\n"); }, 0,
                   {"not an STL file: no ASCII \"solid\" header"});
}

// ------------------------------------------------------------ OFF

TEST(OffReader, HeaderVariantsCommentsAndPolygons) {
  const std::string body =
      "# vertices\n"
      "0 0 0\n1 0 0 # a comment\n1 1 0 255 0 0\n0 1 0\n\n2 0 0\n2 1 0\n"
      "3 0 1 2\n"
      "4 0 1 2 3 0.5 0.5 0.5\n"  // a quad with a colour
      "6 1 4 5 2 3 0\n";         // a hexagon: fan of 4
  const std::vector<std::int64_t> tris = {0, 1, 2, 1, 4, 5, 1, 5, 2, 1, 2, 3, 1, 3, 0};
  for (const std::string& header : {std::string("OFF\n6 3 0\n"), std::string("# c\n\nOFF 6 3 9\n"),
                                    std::string("COFF\n# counts next\n6 3 0\n"), std::string("6 3 0\n")}) {
    SCOPED_TRACE(header);
    const Geometry g = Off(header + body);
    ASSERT_EQ(g.patches.size(), 2u);
    EXPECT_EQ(g.patches[0].cell, CellType::Tri);
    EXPECT_EQ(g.patches[0].points, std::vector<double>({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 2, 0, 0, 2, 1, 0}));
    EXPECT_EQ(g.patches[0].cells, tris);
    EXPECT_EQ(g.patches[1].cell, CellType::Quad);
    EXPECT_EQ(g.patches[1].cells, std::vector<std::int64_t>({0, 1, 2, 3}));
  }
}

TEST(OffReader, Errors) {
  const std::string v3 = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n";
  ExpectInputError([&] { Off(""); }, 1, {"m.off:1: empty file"});
  ExpectInputError([&] { Off("# only a comment\n"); }, 1, {"empty file"});
  ExpectInputError([&] { Off("PLY\n"); }, 1,
                   {"expected the \"OFF\" header or the vertex and face counts, found \"PLY\""});
  ExpectInputError([&] { Off("4OFF\n"); }, 1, {"unsupported OFF variant \"4OFF\""});
  ExpectInputError([&] { Off("OFF\n"); }, 1, {"unexpected end of file, expected the vertex and face counts"});
  ExpectInputError([&] { Off("OFF\n3\n"); }, 2, {"expected the face count"});
  ExpectInputError([&] { Off("OFF\n-3 1 0\n"); }, 2, {"vertex count: \"-3\" is not a non-negative integer"});
  ExpectInputError([&] { Off("OFF\nthree 1 0\n"); }, 2, {"vertex count: \"three\""});
  // Absurd counts are refused before anything is allocated.
  ExpectInputError([&] { Off("OFF\n1000000000000 1 0\n0 0 0\n"); }, 2,
                   {"the header declares 1000000000000 vertices and 1 faces, more than the remaining 6 bytes"});
  ExpectInputError([&] { Off("OFF\n9223372036854775807 9223372036854775807 0\n"); }, 2, {"more than the remaining"});
  ExpectInputError([&] { Off("OFF\n3 1 0\n0 0 0\n1 0 0\n"); }, 2, {"more than the remaining"});
  // A file that holds its header's claims is read to its real fault.
  ExpectInputError([&] { Off("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n"); }, 6,
                   {"face 0: 2 vertices, a face needs at least 3"});
  ExpectInputError([&] { Off("OFF\n3 0 0\n0 0 0\n1 0 0\n# padding padding\n"); }, 5,
                   {"unexpected end of file after 2 of 3 vertices"});
  ExpectInputError([&] { Off("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n# padding\n"); }, 7,
                   {"unexpected end of file after 1 of 2 faces"});
  ExpectInputError([&] { Off(v3 + "3 0 1 3\n"); }, 6,
                   {"m.off:6: face 0: vertex index 3 out of range (the file has 3 vertices, numbered from 0)"});
  ExpectInputError([&] { Off(v3 + "3 0 -1 2\n"); }, 6, {"face 0: vertex index -1 out of range"});
  ExpectInputError([&] { Off(v3 + "2 0 1 # pad\n"); }, 6, {"face 0: 2 vertices, a face needs at least 3"});
  ExpectInputError([&] { Off(v3 + "3 0 1 # pad\n"); }, 6, {"face 0: 2 vertex indices, expected 3"});
  ExpectInputError([&] { Off(v3 + "1000000000 0 1 2\n"); }, 6, {"face 0: 3 vertex indices, expected 1000000000"});
  ExpectInputError([&] { Off(v3 + "3 0 1 b\n"); }, 6, {"face 0: vertex index \"b\" is not an integer"});
  ExpectInputError([&] { Off(v3 + "x 0 1 2\n"); }, 6, {"face 0: vertex count \"x\" is not an integer"});
  ExpectInputError([&] { Off("OFF\n3 1 0\n0 0 0\n1 0 \t \n0 1 0\n3 0 1 2\n"); }, 4,
                   {"vertex 1: 2 coordinates, expected 3"});
  ExpectInputError([&] { Off("OFF\n3 1 0\n0 0 0\n1 -nan 0\n0 1 0\n3 0 1 2\n"); }, 4,
                   {"vertex 1: coordinate 1: \"-nan\" is not a finite number"});
  ExpectInputError([&] { Off("OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n"); }, 5, {"no faces"});
  // A header that declares fewer faces than the file holds: the extra ones
  // would be dropped unseen. Comments and blank lines after the last are no data.
  ExpectInputError([&] { Off(v3 + "3 0 1 2\n\n# end\n3 2 1 0\n"); }, 9,
                   {"m.off:9: data after the last of the 1 faces the header declares"});
  EXPECT_EQ(Off(v3 + "3 0 1 2\n\n# end\n").patches[0].cells.size(), 3u);
}

// ------------------------------------------------------------ files and dispatch

TEST(MeshFiles, DispatchByExtensionAndFileErrors) {
  TempDir dir;
  const std::string quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
  EXPECT_EQ(ReadMeshFile(dir.Write("a.obj", quad)).patches.size(), 1u);
  EXPECT_EQ(ReadGeometryFile(dir.Write("b.OBJ", quad)).patches[0].cell, CellType::Quad);
  EXPECT_EQ(ReadGeometryFile(dir.Write("c.stl", BinaryStl(kTwoTriangles))).patches[0].cells.size(), 6u);
  EXPECT_EQ(ReadGeometryFile(dir.Write("d.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")).patches.size(), 1u);
  ExpectInputError([&] { ReadMeshFile(dir.Write("e.ply", quad)); }, 0,
                   {"unknown mesh file extension \".ply\" (supported: .obj, .stl, .off)"});
  ExpectInputError(
      [&] { ReadGeometryFile(dir.Write("f.xyz", quad)); }, 0,
      {"f.xyz", "unknown geometry file extension \".xyz\" (supported: .json, .obj, .stl, .off, .ply, .msh)"});
  ExpectInputError([&] { ReadGeometryFile(dir.Write("noext", quad)); }, 0, {"no file extension"});
  ExpectInputError([&] { ReadMeshFile(dir.Path("missing.obj")); }, 0, {"missing.obj", "no such file"});
  ExpectInputError([&] { ReadGeometryFile(dir.Path("missing.stl")); }, 0, {"missing.stl", "no such file"});
  std::filesystem::create_directories(dir.Path("folder.off"));
  ExpectInputError([&] { ReadMeshFile(dir.Path("folder.off")); }, 0, {"folder.off", "directory"});
  ExpectInputError([&] { ReadMeshFile(dir.Write("empty.obj", "")); }, 1, {"empty.obj:1: no faces"});
  ExpectInputError([&] { ReadMeshFile(dir.Write("empty.stl", "")); }, 0, {"empty.stl: not an STL file"});
  ExpectInputError([&] { ReadMeshFile(dir.Write("empty.off", "")); }, 1, {"empty.off:1: empty file"});
}

TEST(MeshFiles, TruncatedFilesAlwaysFailCleanly) {
  const std::string obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
  const std::string off = "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
  const std::string stl =
      "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\nendloop\nendfacet\nendsolid "
      "s\n";
  const std::string binary = BinaryStl(kTwoTriangles);
  // Every proper prefix is either an error or (OBJ, cut after a whole face)
  // a valid smaller mesh; none may crash, hang or allocate wildly.
  for (std::size_t cut = 0; cut < obj.size(); ++cut) {
    try {
      EXPECT_EQ(Obj(obj.substr(0, cut)).patches.size(), 1u) << cut;
    } catch (const InputError&) {
    }
  }
  for (std::size_t cut = 0; cut + 1 < off.size(); ++cut) EXPECT_THROW(Off(off.substr(0, cut)), InputError) << cut;
  for (std::size_t cut = 0; cut + 9 < stl.size(); ++cut) EXPECT_THROW(Stl(stl.substr(0, cut)), InputError) << cut;
  for (std::size_t cut = 0; cut < binary.size(); ++cut) EXPECT_THROW(Stl(binary.substr(0, cut)), InputError) << cut;
}

// ------------------------------------------------------------ round trips

TEST(MeshFiles, RoundTripUnitSquareFromEachFormat) {
  const Geometry fromObj = Obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  const Geometry fromOff = Off("OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
  const Geometry fromStl = Stl(BinaryStl(kTwoTriangles));
  for (const Geometry* g : {&fromObj, &fromOff, &fromStl}) {
    const Closest c = Query(*g, 0.3, 0.4, 2.0);
    ASSERT_EQ(c.status, Status::Found);
    EXPECT_NEAR(c.point[0], 0.3, 1e-12);
    EXPECT_NEAR(c.point[1], 0.4, 1e-12);
    EXPECT_NEAR(c.point[2], 0.0, 1e-12);
    EXPECT_NEAR(c.distance, 2.0, 1e-12);
  }
  // (0.3, 0.4) lies in the second triangle (0, 2, 3) of the split square.
  EXPECT_EQ(Query(fromOff, 0.3, 0.4, 2.0).cell, 1);
  EXPECT_EQ(Query(fromOff, 0.4, 0.3, 2.0).cell, 0);
}

TEST(MeshFiles, RoundTripCubeFromAsciiStl) {
  // The unit cube as 12 triangles; the closest point of (0.5, 0.25, 3) is
  // (0.5, 0.25, 1) on the top face, of (2, 2, 2) the corner (1, 1, 1).
  std::string stl = "solid cube\n";
  const int faces[6][4][3] = {
      {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}, {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
      {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}, {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}},
      {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}}, {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}};
  for (const auto& f : faces) {
    const int order[2][3] = {{0, 1, 2}, {0, 2, 3}};
    for (const auto& o : order) {
      stl += "facet normal 0 0 0\nouter loop\n";
      for (int v : o) {
        stl +=
            "vertex " + std::to_string(f[v][0]) + " " + std::to_string(f[v][1]) + " " + std::to_string(f[v][2]) + "\n";
      }
      stl += "endloop\nendfacet\n";
    }
  }
  stl += "endsolid cube\n";
  const Geometry g = Stl(stl);
  ASSERT_EQ(g.patches.size(), 1u);
  EXPECT_EQ(g.patches[0].points.size(), 8u * 3);  // corners merged
  EXPECT_EQ(g.patches[0].cells.size(), 12u * 3);
  const Closest top = Query(g, 0.5, 0.25, 3.0);
  EXPECT_NEAR(top.point[0], 0.5, 1e-12);
  EXPECT_NEAR(top.point[1], 0.25, 1e-12);
  EXPECT_NEAR(top.point[2], 1.0, 1e-12);
  EXPECT_NEAR(top.distance, 2.0, 1e-12);
  const Closest corner = Query(g, 2.0, 2.0, 2.0);
  EXPECT_NEAR(corner.distance, std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(corner.point[0] + corner.point[1] + corner.point[2], 3.0, 1e-12);
}

}  // namespace
}  // namespace invmap::io

namespace invmap::io {
namespace {

// ------------------------------------------------------------ hostile inputs

namespace hostile {

/// A stream that cannot seek (its size is unknown, as a pipe's or a device's):
/// `prefix`, then `filler` repeated forever (or nothing when `endless` is false).
class EndlessBuffer : public std::streambuf {
 public:
  EndlessBuffer(std::string prefix, char filler, bool endless)
      : prefix_(std::move(prefix)), block_(1 << 16, filler), endless_(endless) {
    setg(prefix_.data(), prefix_.data(), prefix_.data() + prefix_.size());
  }
  /// Bytes handed out so far.
  std::size_t delivered() const { return delivered_ + static_cast<std::size_t>(gptr() - eback()); }

 protected:
  int_type underflow() override {
    delivered_ += static_cast<std::size_t>(egptr() - eback());
    if (!endless_) {
      setg(block_.data(), block_.data(), block_.data());
      return traits_type::eof();
    }
    setg(block_.data(), block_.data(), block_.data() + block_.size());
    return traits_type::to_int_type(block_[0]);
  }

 private:
  std::string prefix_;
  std::string block_;
  bool endless_;
  std::size_t delivered_ = 0;
};

}  // namespace hostile

TEST(MeshFiles, EndlessInputsFailAfterABoundedRead) {
  // /dev/zero under every text format's name: each stops within a line limit.
  using Reader = Geometry (*)(std::istream&, const std::string&);
  const std::pair<const char*, Reader> readers[] = {{"m.obj", ReadObj}, {"m.off", ReadOff}, {"m.stl", ReadStl}};
  for (const auto& [name, read] : readers) {
    SCOPED_TRACE(name);
    hostile::EndlessBuffer zeros("", '\0', true);
    std::istream in(&zeros);
    EXPECT_THROW(read(in, name), InputError);
    // The buffer doubles up to the line limit: twice it at most.
    EXPECT_LE(zeros.delivered(), 2 * InputBuffer::kMaxLineBytes + (std::size_t{2} << 20));
  }
  // An STL of zeros: a binary header of 0 triangles, then more bytes.
  hostile::EndlessBuffer zeros("", '\0', true);
  std::istream in(&zeros);
  ExpectInputError([&] { ReadStl(in, "z.stl"); }, 0, {"z.stl: not an STL file: more bytes after the 0 triangles"});
  EXPECT_LE(zeros.delivered(), std::size_t{2} << 20);
  // An endless OBJ of valid lines is read as far as memory goes, like any
  // large file; an endless line is refused at the line limit.
  hostile::EndlessBuffer longLine("v 0 0 0\nf 1 1 1", ' ', true);
  std::istream lineIn(&longLine);
  ExpectInputError([&] { ReadObj(lineIn, "l.obj"); }, 2, {"line longer than 64 MiB"});
}

TEST(MeshFiles, AStreamOfUnknownSizeIsReadByItsHeader) {
  const std::vector<std::array<float, 9>> triangles = {{0, 0, 0, 1, 0, 0, 0, 1, 0}, {1, 0, 0, 1, 1, 0, 0, 1, 0}};
  {
    hostile::EndlessBuffer pipe(BinaryStl(triangles), 'x', false);
    std::istream in(&pipe);
    const Geometry g = ReadStl(in, "p.stl");
    ASSERT_EQ(g.patches.size(), 1u);
    EXPECT_EQ(g.patches[0].cells.size(), 6u);
    EXPECT_EQ(g.patches[0].points.size(), 12u);
  }
  {
    hostile::EndlessBuffer pipe(BinaryStl(triangles) + "trailing", 'x', false);
    std::istream in(&pipe);
    ExpectInputError([&] { ReadStl(in, "p.stl"); }, 0, {"more bytes after the 2 triangles"});
  }
  {
    hostile::EndlessBuffer pipe(BinaryStl(triangles, "binary", 3), 'x', false);
    std::istream in(&pipe);
    ExpectInputError([&] { ReadStl(in, "p.stl"); }, 0, {"the file ends in triangle 2 of the 3"});
  }
  {
    hostile::EndlessBuffer pipe("solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
                                "endloop\nendfacet\nendsolid s\n",
                                'x', false);
    std::istream in(&pipe);
    EXPECT_EQ(ReadStl(in, "p.stl").patches[0].cells.size(), 3u);
  }
  {
    hostile::EndlessBuffer pipe("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", 'x', false);
    std::istream in(&pipe);
    EXPECT_EQ(ReadOff(in, "p.off").patches[0].cells.size(), 3u);
  }
  {
    // Counts a pipe cannot back are not reserved: the file ends first.
    hostile::EndlessBuffer pipe("OFF\n1000000000000 1000000000000 0\n0 0 0\n", 'x', false);
    std::istream in(&pipe);
    ExpectInputError([&] { ReadOff(in, "p.off"); }, 3, {"unexpected end of file after 1 of 1000000000000 vertices"});
  }
}

TEST(MeshFiles, HugeSparseFilesAreRefusedFromTheirSizeAndFirstBytes) {
  TempDir dir;
  // Sparse files: their size costs no disk, and their bytes read as zeros.
  const auto sparse = [&](const std::string& name, std::uintmax_t size) {
    const std::string path = dir.Write(name, "");
    std::filesystem::resize_file(path, size);
    return path;
  };
  ExpectInputError([&] { ReadMeshFile(sparse("big.stl", std::uintmax_t{6} << 30)); }, 0,
                   {"not an STL file: no ASCII \"solid\" header", "this file has 6442450944"});
  ExpectInputError([&] { ReadMeshFile(sparse("big.obj", std::uintmax_t{2} << 30)); }, 1, {"line longer than 64 MiB"});
  ExpectInputError([&] { ReadMeshFile(sparse("big.off", std::uintmax_t{2} << 30)); }, 1, {"line longer than 64 MiB"});
  ExpectInputError([&] { ReadGeometryFile(sparse("big.json", std::uintmax_t{2} << 30)); }, 1,
                   {"a NUL byte (binary data, not a JSON text)"});
}

/// The triangles of a face of `n` indices in OBJ, as read.
std::vector<std::int64_t> ObjFaceTriangles(const std::vector<int>& face, int vertices) {
  std::string text;
  for (int v = 0; v < vertices; ++v) text += "v " + std::to_string(v) + " " + std::to_string(v * v % 7) + " 0\n";
  text += "f";
  for (int v : face) text += " " + std::to_string(v + 1);
  text += "\n";
  const Geometry g = Obj(text);
  return g.patches.at(0).cells;
}

TEST(MeshFiles, DegenerateFanTrianglesAreLeftOutButTheFaceCoversTheSamePoints) {
  // 3 vertices repeated 100,000 times: of the fan's 299,998 triangles,
  // 199,998 repeat a vertex and the others are all (0, 1, 2).
  std::vector<int> face;
  for (int i = 0; i < 100000; ++i) face.insert(face.end(), {0, 1, 2});
  EXPECT_EQ(ObjFaceTriangles(face, 3), (std::vector<std::int64_t>{0, 1, 2}));
  // Every index the same: one triangle (the point).
  EXPECT_EQ(ObjFaceTriangles({4, 4, 4, 4, 4, 4}, 5), (std::vector<std::int64_t>{4, 4, 4}));
  // Against the fan itself, on random faces with repeats: every fan
  // triangle of three distinct indices is kept (in some vertex order), and
  // every other one's segment from v0 (or the point v0) is an edge of a
  // kept triangle.
  std::mt19937 rng(7);
  for (int trial = 0; trial < 2000; ++trial) {
    const int vertices = 2 + static_cast<int>(rng() % 5);
    std::vector<int> f(5 + rng() % 8);
    for (int& v : f) v = static_cast<int>(rng() % vertices);
    const std::vector<std::int64_t> tris = ObjFaceTriangles(f, vertices);
    SCOPED_TRACE(::testing::PrintToString(f));
    ASSERT_EQ(tris.size() % 3, 0u);
    ASSERT_LE(tris.size() / 3, f.size() - 2);
    // The same three vertices in any order are the same points.
    const auto hasTriangle = [&](std::int64_t a, std::int64_t b, std::int64_t c) {
      std::array<std::int64_t, 3> wanted{a, b, c};
      std::sort(wanted.begin(), wanted.end());
      for (std::size_t t = 0; t < tris.size(); t += 3) {
        std::array<std::int64_t, 3> have{tris[t], tris[t + 1], tris[t + 2]};
        std::sort(have.begin(), have.end());
        if (have == wanted) return true;
      }
      return false;
    };
    const auto hasEdge = [&](std::int64_t a, std::int64_t b) {
      for (std::size_t t = 0; t < tris.size(); t += 3) {
        const std::int64_t* v = &tris[t];
        const bool holdsA = v[0] == a || v[1] == a || v[2] == a, holdsB = v[0] == b || v[1] == b || v[2] == b;
        if (holdsA && holdsB) return true;
      }
      return false;
    };
    for (std::size_t i = 1; i + 1 < f.size(); ++i) {
      const int a = f[0], b = f[i], c = f[i + 1];
      if (a != b && b != c && c != a) {
        EXPECT_TRUE(hasTriangle(a, b, c)) << "fan triangle " << i;
      } else {
        EXPECT_TRUE(hasEdge(a, b != a ? b : c)) << "fan triangle " << i;
      }
    }
  }
}

TEST(MeshFiles, CoordinatesOutsideTheSupportedRangeNameTheirLine) {
  ExpectInputError([] { Obj("v 0 0 0\nv 1 0 0\nv 0 1e200 0\nf 1 2 3\n"); }, 3,
                   {"m.obj:3: v: coordinate 1: \"1e200\" is outside [-1e100, 1e100]"});
  ExpectInputError([] { Off("OFF\n3 1 0\n0 0 0\n-2e100 0 0\n0 1 0\n3 0 1 2\n"); }, 4,
                   {"vertex 1: coordinate 0: \"-2e100\" is outside [-1e100, 1e100]"});
  ExpectInputError(
      [] {
        Stl("solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 1e101\n"
            "endloop\nendfacet\nendsolid s\n");
      },
      6, {"vertex: coordinate 2: \"1e101\" is outside [-1e100, 1e100]"});
}

}  // namespace
}  // namespace invmap::io
