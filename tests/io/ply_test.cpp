// The PLY core (io/ply.h): headers, records of every type in the three
// formats, validation of lying or broken files, and the mesh reader
// (io/ply_mesh.h).
#include "io/ply.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "io/input_error.h"
#include "io/mesh_readers.h"
#include "io/ply_mesh.h"
#include "tests/io/io_scratch.h"

namespace invmap::io {
namespace {

using scratch::ExpectInputError;
using scratch::Put;
using scratch::ScratchDir;

/// Header of a file with a vertex element of every scalar type (both
/// spellings) and a face element with a uchar/int list.
std::string AllTypesHeader(const std::string& format, int vertices, int faces) {
  return "ply\nformat " + format + " 1.0\ncomment made by ply_test\nobj_info anything goes\n" + "element vertex " +
         std::to_string(vertices) +
         "\nproperty char a\nproperty uint8 b\nproperty short c\nproperty uint16 d\n"
         "property int32 e\nproperty uint f\nproperty float32 g\nproperty double h\n"
         "element face " +
         std::to_string(faces) + "\nproperty list uchar int vertex_indices\nend_header\n";
}

/// Values of the two vertices of AllTypesHeader's file.
const double kVertexValues[2][8] = {{-128, 255, -32768, 65535, -2147483648.0, 4294967295.0, 0.5, 0.1},
                                    {127, 0, 32767, 0, 2147483647, 0, -1.25, -1e300}};

/// A binary AllTypes file (2 vertices, faces {0 1 2} and {}).
std::string AllTypesBinary(bool bigEndian) {
  std::string bytes = AllTypesHeader(bigEndian ? "binary_big_endian" : "binary_little_endian", 2, 2);
  for (const auto& v : kVertexValues) {
    Put<std::int8_t>(&bytes, static_cast<std::int8_t>(v[0]), bigEndian);
    Put<std::uint8_t>(&bytes, static_cast<std::uint8_t>(v[1]), bigEndian);
    Put<std::int16_t>(&bytes, static_cast<std::int16_t>(v[2]), bigEndian);
    Put<std::uint16_t>(&bytes, static_cast<std::uint16_t>(v[3]), bigEndian);
    Put<std::int32_t>(&bytes, static_cast<std::int32_t>(v[4]), bigEndian);
    Put<std::uint32_t>(&bytes, static_cast<std::uint32_t>(v[5]), bigEndian);
    Put<float>(&bytes, static_cast<float>(v[6]), bigEndian);
    Put<double>(&bytes, v[7], bigEndian);
  }
  Put<std::uint8_t>(&bytes, 3, bigEndian);
  for (int i : {0, 1, 2}) Put<std::int32_t>(&bytes, i, bigEndian);
  Put<std::uint8_t>(&bytes, 0, bigEndian);
  return bytes;
}

std::string AllTypesAscii() {
  return AllTypesHeader("ascii", 2, 2) +
         "-128 255 -32768 65535 -2147483648 4294967295 0.5 0.1\n"
         "127 +0 32767 0 2147483647 0 -1.25 -1e300\n"
         "3 0 1 2\n"
         "\n"  // blank lines are not records
         "0\n";
}

void CheckAllTypes(PlyReader& reader) {
  const PlyHeader& header = reader.header();
  ASSERT_EQ(header.elements.size(), 2u);
  EXPECT_EQ(header.elements[0].name, "vertex");
  EXPECT_EQ(header.elements[0].count, 2);
  ASSERT_EQ(header.elements[0].properties.size(), 8u);
  const PlyType types[8] = {PlyType::Int8,  PlyType::UInt8,  PlyType::Int16,   PlyType::UInt16,
                            PlyType::Int32, PlyType::UInt32, PlyType::Float32, PlyType::Float64};
  for (int p = 0; p < 8; ++p) EXPECT_EQ(header.elements[0].properties[p].type, types[p]) << p;
  EXPECT_TRUE(header.elements[1].properties[0].isList);
  EXPECT_EQ(header.elements[1].properties[0].countType, PlyType::UInt8);
  EXPECT_EQ(header.elements[1].properties[0].type, PlyType::Int32);
  EXPECT_EQ(header.elements[1].headerLine, 13u);
  EXPECT_EQ(header.lines.front(), "ply");
  EXPECT_EQ(header.lines[2], "comment made by ply_test");
  EXPECT_EQ(header.lines[3], "obj_info anything goes");
  EXPECT_EQ(header.lines.back(), "end_header");
  EXPECT_EQ(header.FindElement("face"), 1);
  EXPECT_EQ(header.FindElement("edge"), -1);
  EXPECT_EQ(header.elements[0].FindProperty("h"), 7);

  PlyRecord record;
  for (const auto& expected : kVertexValues) {
    ASSERT_TRUE(reader.ReadRecord(&record));
    ASSERT_EQ(record.values.size(), 8u);
    for (int p = 0; p < 8; ++p) {
      // float32 values are the float nearest to the number.
      const double want = p == 6 ? static_cast<double>(static_cast<float>(expected[p])) : expected[p];
      EXPECT_EQ(record.Scalar(static_cast<std::size_t>(p)), want) << p;
    }
  }
  EXPECT_FALSE(reader.ReadRecord(&record));
  EXPECT_EQ(reader.element(), 0u);
  reader.NextElement();
  ASSERT_TRUE(reader.ReadRecord(&record));
  ASSERT_EQ(record.ListSize(0), 3u);
  EXPECT_EQ(record.List(0)[2], 2.0);
  ASSERT_TRUE(reader.ReadRecord(&record));
  EXPECT_EQ(record.ListSize(0), 0u);
  EXPECT_FALSE(reader.ReadRecord(&record));
  reader.NextElement();
  EXPECT_EQ(reader.element(), 2u);
  EXPECT_FALSE(reader.ReadRecord(&record));
}

TEST(PlyReader, ReadsEveryTypeInEveryFormat) {
  ScratchDir dir;
  {
    SCOPED_TRACE("ascii");
    PlyReader reader(dir.Write("a.ply", AllTypesAscii()));
    EXPECT_EQ(reader.header().format, PlyFormat::Ascii);
    CheckAllTypes(reader);
  }
  for (bool bigEndian : {false, true}) {
    SCOPED_TRACE(bigEndian ? "big endian" : "little endian");
    PlyReader reader(dir.Write("b.ply", AllTypesBinary(bigEndian)));
    EXPECT_EQ(reader.header().format, bigEndian ? PlyFormat::BinaryBigEndian : PlyFormat::BinaryLittleEndian);
    CheckAllTypes(reader);
  }
}

TEST(PlyReader, ReadsFromAStream) {
  PlyReader reader(std::make_unique<std::istringstream>(AllTypesBinary(false)), "memory.ply");
  EXPECT_EQ(reader.name(), "memory.ply");
  CheckAllTypes(reader);
}

/// An input stream that cannot seek (a pipe), so its size is unknown.
class PipeStream : public std::istream {
 public:
  explicit PipeStream(std::string data) : std::istream(nullptr), buffer_(std::move(data)) { rdbuf(&buffer_); }

 private:
  /// A read-only buffer over a string without seekoff/seekpos.
  class Buffer : public std::streambuf {
   public:
    explicit Buffer(std::string data) : data_(std::move(data)) {
      setg(data_.data(), data_.data(), data_.data() + data_.size());
    }

   private:
    std::string data_;  ///< The bytes to deliver.
  };
  Buffer buffer_;  ///< The stream's buffer.
};

TEST(PlyReader, UnknownSizeStreamsFailWhenTheDataRunsOut) {
  // The header cannot be checked against a size, so 4 billion vertices are
  // believed until the data ends; neither reading nor the mesh reader may
  // reserve for them.
  const std::string lying =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n" +
      std::string(40, '\0');
  PlyReader reader(std::make_unique<PipeStream>(lying), "pipe.ply");
  EXPECT_FALSE(reader.countsChecked());
  PlyRecord record;
  ExpectInputError(
      [&] {
        while (reader.ReadRecord(&record)) {
        }
      },
      "pipe.ply", 0, "the file ends in 'vertex' record 3 of 4000000000");
  ExpectInputError([&] { ReadPlyMesh(std::make_unique<PipeStream>(lying), "pipe.ply"); }, "pipe.ply", 0,
                   "the file ends in 'vertex' record 3");
  // A list count that a corrupt stream cannot back: the buffer grows only
  // with the data read.
  std::string longList =
      "ply\nformat binary_little_endian 1.0\nelement face 1\n"
      "property list uint double vertex_indices\nend_header\n";
  Put<std::uint32_t>(&longList, 16000000u);
  longList += std::string(1000, '\0');
  PlyReader listReader(std::make_unique<PipeStream>(longList), "pipe.ply");
  ExpectInputError([&] { listReader.ReadRecord(&record); }, "pipe.ply", 0, "the file ends in 'face' record 0");
}

TEST(PlyReader, RawRecordsAreVerbatim) {
  ScratchDir dir;
  const std::string binary = AllTypesBinary(true);
  PlyReader reader(dir.Write("b.ply", binary));
  std::string raw;
  PlyRecord record;
  while (reader.ReadRecord(&record, &raw)) {
  }
  reader.NextElement();
  while (reader.ReadRecord(&record, &raw)) {
  }
  EXPECT_EQ(raw, binary.substr(static_cast<std::size_t>(reader.header().dataOffset)));

  // Ascii: the lines with their terminators; CRLF is kept, a missing final
  // newline is added.
  PlyReader ascii(
      dir.Write("a.ply", "ply\r\nformat ascii 1.0\r\nelement vertex 2\r\nproperty float x\r\nend_header\r\n1.5\r\n2"));
  raw.clear();
  ASSERT_TRUE(ascii.ReadRecord(&record, &raw));
  EXPECT_EQ(record.Scalar(0), 1.5);
  ASSERT_TRUE(ascii.ReadRecord(&record, &raw));
  EXPECT_EQ(raw, "1.5\r\n2\n");
}

TEST(PlyReader, SkipsToAnElement) {
  ScratchDir dir;
  // Faces before vertices, with a fixed-size element and a list element to skip.
  std::string bytes =
      "ply\nformat binary_little_endian 1.0\nelement face 2\nproperty list uchar uint vertex_indices\n"
      "element pad 3\nproperty double p\nelement vertex 1\nproperty float x\nend_header\n";
  Put<std::uint8_t>(&bytes, 1);
  Put<std::uint32_t>(&bytes, 7);
  Put<std::uint8_t>(&bytes, 2);
  Put<std::uint32_t>(&bytes, 8);
  Put<std::uint32_t>(&bytes, 9);
  for (int i = 0; i < 3; ++i) Put<double>(&bytes, i);
  Put<float>(&bytes, 42.0f);
  PlyReader reader(dir.Write("s.ply", bytes));
  reader.SkipToElement(2);
  PlyRecord record;
  ASSERT_TRUE(reader.ReadRecord(&record));
  EXPECT_EQ(record.Scalar(0), 42.0);
}

TEST(PlyReader, TypeNames) {
  PlyType type;
  EXPECT_TRUE(ParsePlyType("float64", &type));
  EXPECT_EQ(type, PlyType::Float64);
  EXPECT_TRUE(ParsePlyType("uchar", &type));
  EXPECT_EQ(type, PlyType::UInt8);
  EXPECT_FALSE(ParsePlyType("int64", &type));
  EXPECT_STREQ(PlyTypeName(PlyType::UInt16), "ushort");
  EXPECT_EQ(PlyTypeSize(PlyType::Float32), 4);
  EXPECT_EQ(PlyPatchableCount(1234), "1234\ncomment         ");
  EXPECT_EQ(PlyPatchableCount(0).size(), static_cast<std::size_t>(kPlyPatchableCountBytes));
  EXPECT_EQ(PlyPatchableCount(999999999999).size(), static_cast<std::size_t>(kPlyPatchableCountBytes));
  EXPECT_THROW(PlyPatchableCount(std::int64_t{1000000000000}), std::length_error);
}

/// Expects opening `content` as a PLY file (or, with `readAll`, reading all
/// its records) to fail with `part` in the message at `line`.
void ExpectBadPly(const std::string& content, std::int64_t line, const std::string& part, bool readAll = false) {
  ScratchDir dir;
  const std::string path = dir.Write("bad.ply", content);
  ExpectInputError(
      [&] {
        PlyReader reader(path);
        PlyRecord record;
        while (readAll && reader.element() < reader.header().elements.size()) {
          while (reader.ReadRecord(&record)) {
          }
          reader.NextElement();
        }
      },
      path, line, part);
}

TEST(PlyReader, RejectsBadHeaders) {
  ExpectBadPly("", 0, "empty file");
  ExpectBadPly("solid cube\n", 1, "not a PLY file");
  ExpectBadPly("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", 4, "no end_header");
  ExpectBadPly("ply\nformat ebcdic 1.0\nend_header\n", 2, "unknown PLY format");
  ExpectBadPly("ply\nformat ascii 2.0\nend_header\n", 2, "unsupported PLY version");
  ExpectBadPly("ply\nelement vertex 1\nproperty float x\nend_header\n1\n", 4, "no format line");
  ExpectBadPly("ply\nformat ascii 1.0\nproperty float x\nend_header\n", 3, "property before any element");
  ExpectBadPly("ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n", 4,
               "unknown property type 'float128'");
  ExpectBadPly("ply\nformat ascii 1.0\nelement face 1\nproperty list float int v\nend_header\n", 4,
               "not an integer type");
  ExpectBadPly("ply\nformat ascii 1.0\nelement vertex -1\nend_header\n", 3, "bad element count");
  ExpectBadPly("ply\nformat ascii 1.0\nelement vertex many\nend_header\n", 3, "bad element count");
  ExpectBadPly("ply\nformat ascii 1.0\nelement vertex 1\nend_header\n\n", 0, "no properties");
  ExpectBadPly("ply\nformat ascii 1.0\nbogus line\nend_header\n", 3, "unknown header line 'bogus'");
}

TEST(PlyReader, RejectsHeadersThatPromiseMoreThanTheFileHolds) {
  // 4 billion vertices in a file of about 100 bytes: refused at once,
  // before any allocation, in every format.
  for (const char* format : {"binary_little_endian", "binary_big_endian", "ascii"}) {
    std::string content =
        std::string("ply\nformat ") + format + " 1.0\nelement vertex 4000000000\nproperty float x\nend_header\n";
    content.resize(100, '\0');
    ExpectBadPly(content, 0, "declares 4000000000 'vertex' records");
  }
  // A second element that does not fit after the first one.
  std::string content =
      "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty double x\n"
      "element face 100\nproperty list uchar int vertex_indices\nend_header\n";
  content += std::string(16 + 99, '\0');
  ExpectBadPly(content, 0, "declares 100 'face' records");
}

TEST(PlyReader, RejectsBrokenData) {
  const std::string binaryHeader =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty double x\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  // The count fits the size check (1 byte per face) but the list does not.
  std::string truncated = binaryHeader;
  Put<double>(&truncated, 1.0);
  Put<std::uint8_t>(&truncated, 3);
  Put<std::int32_t>(&truncated, 0);
  ExpectBadPly(truncated, 0, "the file ends in 'face' record 0 of 1", true);

  std::string longList =
      "ply\nformat binary_little_endian 1.0\nelement face 1\n"
      "property list uint uchar vertex_indices\nend_header\n";
  Put<std::uint32_t>(&longList, 4000000000u);
  longList += std::string(64, '\0');
  ExpectBadPly(longList, 0, "bad length 4000000000", true);

  const std::string asciiHeader =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty uchar c\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  ExpectBadPly(asciiHeader + "1 2\n1.5x 3\n3 0 1 1\n", 10, "'1.5x' is not a number", true);
  ExpectBadPly(asciiHeader + "1 2\n1 256\n3 0 1 1\n", 10, "'256' is not a valid uchar", true);
  ExpectBadPly(asciiHeader + "1 2\n1\n3 0 1 1\n", 10, "too few values", true);
  ExpectBadPly(asciiHeader + "1 2\n1 2 3\n3 0 1 1\n", 10, "too many values", true);
  ExpectBadPly(asciiHeader + "1 2\n1 2\n3 0 1\n", 11, "too few values", true);
  ExpectBadPly(asciiHeader + "1 2\n1 2\n3 0 1 2 3\n", 11, "too many values", true);
  ExpectBadPly(asciiHeader + "1 2\n1 2\n\n\n\n", 14, "ends in 'face' record 0 of 1", true);
}

TEST(PlyReader, RejectsMissingFilesAndDirectories) {
  ScratchDir dir;
  ExpectInputError([&] { PlyReader reader(dir.Path("none.ply")); }, dir.Path("none.ply"), 0, "no such file");
  ExpectInputError([&] { PlyReader reader(dir.path().string()); }, dir.path().string(), 0, "is a directory");
}

// ---------------------------------------------------------------------------
// ReadPlyMesh

/// A unit square split into a triangle pair, a quad beside it and a
/// pentagon above, as an ascii PLY file.
std::string MixedMeshAscii(const char* listName = "vertex_indices") {
  return std::string(
             "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
             "property uchar red\nelement face 4\nproperty list uchar int ") +
         listName +
         "\nend_header\n"
         "0 0 0 1\n1 0 0 2\n1 1 0 3\n0 1 0 4\n2 0 0 5\n2 1 0 6\n0.5 2 0 7\n1.5 2 0 8\n"
         "3 0 1 2\n3 0 2 3\n4 1 4 5 2\n5 3 2 5 7 6\n";
}

TEST(ReadPlyMesh, SplitsTrianglesQuadsAndFans) {
  ScratchDir dir;
  for (const char* listName : {"vertex_indices", "vertex_index"}) {
    const Geometry geometry = ReadPlyMesh(dir.Write("m.ply", MixedMeshAscii(listName)));
    EXPECT_EQ(geometry.dimension, 3);
    ASSERT_EQ(geometry.patches.size(), 2u);
    const Patch& tris = geometry.patches[0];
    const Patch& quads = geometry.patches[1];
    EXPECT_EQ(tris.kind, Patch::Kind::Mesh);
    EXPECT_EQ(tris.cell, CellType::Tri);
    EXPECT_EQ(quads.cell, CellType::Quad);
    EXPECT_EQ(tris.cells, (std::vector<std::int64_t>{0, 1, 2, 0, 2, 3, 3, 2, 5, 3, 5, 7, 3, 7, 6}));
    EXPECT_EQ(quads.cells, (std::vector<std::int64_t>{1, 4, 5, 2}));
    ASSERT_EQ(tris.points.size(), 24u);
    EXPECT_EQ(tris.points, quads.points);
    EXPECT_EQ(tris.points[18], 0.5);
    EXPECT_EQ(tris.points[19], 2.0);
  }
}

TEST(ReadPlyMesh, ReadsBinaryAndOnlyQuads) {
  ScratchDir dir;
  std::string bytes =
      "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
      "property double z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n";
  const double xyz[4][3] = {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  for (const auto& p : xyz) {
    for (double c : p) Put<double>(&bytes, c, true);
  }
  Put<std::uint8_t>(&bytes, 4, true);
  for (std::uint32_t i : {0u, 1u, 2u, 3u}) Put<std::uint32_t>(&bytes, i, true);
  const Geometry geometry = ReadPlyMesh(dir.Write("q.ply", bytes));
  ASSERT_EQ(geometry.patches.size(), 1u);
  EXPECT_EQ(geometry.patches[0].cell, CellType::Quad);
  EXPECT_EQ(geometry.patches[0].cells, (std::vector<std::int64_t>{0, 1, 2, 3}));
  EXPECT_EQ(geometry.patches[0].points[11], 1.0);
}

TEST(ReadPlyMesh, WithoutZIsTwoDimensional) {
  ScratchDir dir;
  const Geometry geometry = ReadPlyMesh(
      dir.Write("t.ply",
                "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0\n1 0\n0 1\n3 0 1 2\n"));
  EXPECT_EQ(geometry.dimension, 2);
  EXPECT_EQ(geometry.patches[0].points, (std::vector<double>{0, 0, 1, 0, 0, 1}));
}

TEST(ReadPlyMesh, RejectsBadMeshes) {
  ScratchDir dir;
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n";
  const auto expectBad = [&](const std::string& content, std::int64_t line, const std::string& part) {
    const std::string path = dir.Write("bad.ply", content);
    ExpectInputError([&] { ReadPlyMesh(path); }, path, line, part);
  };
  expectBad(header + "3 0 1 3\n", 13, "vertex index 3 is not in [0, 3)");
  expectBad(header + "3 0 -1 2\n", 13, "vertex index -1");
  expectBad(header + "2 0 1\n", 13, "face 0 has 2 vertices");
  expectBad(header + "3 0 1\n", 13, "too few values");
  expectBad(
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
      "end_header\n0 0 0\n",
      0, "no 'face' element");
  expectBad(
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 0\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n",
      0, "no faces");
  expectBad(
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float z\n"
      "element face 0\nproperty list uchar int vertex_indices\nend_header\n0 0\n",
      0, "no property 'y'");
  expectBad(
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n",
      11, "vertex 1 has a coordinate that is not finite");
}

TEST(ReadPlyMesh, HeadersWhoseFaceCountLiesAreRefusedNamingTheLine) {
  ScratchDir dir;
  const auto header = [](const std::string& format, int faces) {
    return "ply\nformat " + format + " 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
           "property float z\nelement face " + std::to_string(faces) +
           "\nproperty list uchar int vertex_indices\nend_header\n";
  };
  const std::string vertices = "0 0 0\n1 0 0\n0 1 0\n";
  const auto expectBad = [&](const std::string& content, std::int64_t line, const std::string& part) {
    const std::string path = dir.Write("lies.ply", content);
    ExpectInputError([&] { ReadPlyMesh(path); }, path, line, part);
  };
  // Too many: the file ends before the faces it declares (the padding
  // keeps the size check from finding it first); the line named is the
  // one after the last.
  expectBad(header("ascii", 3) + vertices + "3 0 1 2\n\n\n\n\n\n\n\n", 21, "ends in 'face' record 1 of 3");
  // Too few: a face past the declared ones would be dropped unseen.
  expectBad(header("ascii", 1) + vertices + "3 0 1 2\n3 2 1 0\n", 14,
            "data after the last record: the header declares 3 'vertex', 1 'face' records");
  // Blank lines after the last record are no data.
  EXPECT_EQ(ReadPlyMesh(dir.Write("blank.ply", header("ascii", 1) + vertices + "3 0 1 2\n\n  \n")).patches[0].cells,
            (std::vector<std::int64_t>{0, 1, 2}));
  // Binary: a whole extra face is refused, a trailing newline is not.
  std::string binary = header("binary_little_endian", 1);
  const auto putFloat = [&](float x) { binary.append(reinterpret_cast<const char*>(&x), 4); };
  const auto putFace = [&](std::int32_t a, std::int32_t b, std::int32_t c) {
    binary += static_cast<char>(3);
    for (const std::int32_t v : {a, b, c}) binary.append(reinterpret_cast<const char*>(&v), 4);
  };
  for (const float x : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) putFloat(x);
  putFace(0, 1, 2);
  EXPECT_EQ(ReadPlyMesh(dir.Write("one.ply", binary + "\n")).patches[0].cells.size(), 3u);
  putFace(2, 1, 0);
  expectBad(binary, 0, "data after the last record: the header declares 3 'vertex', 1 'face' records");
}

TEST(ReadPlyMesh, HostileFaceCountsReserveNoMoreThanTheFileHolds) {
  // A binary file of a million declared faces: one real triangle, then
  // empty lists (a byte each, so the header's count passes the size
  // check). The triangles' reservation is capped by what the file's bytes
  // could hold at 13 bytes a triangle, and the empty face is named.
  ScratchDir dir;
  std::string content =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1000000\nproperty list uchar int vertex_indices\nend_header\n";
  for (const float x : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) content.append(reinterpret_cast<const char*>(&x), 4);
  content += static_cast<char>(3);
  for (const std::int32_t v : {0, 1, 2}) content.append(reinterpret_cast<const char*>(&v), 4);
  content.append(1000000 - 1, '\0');
  const std::string path = dir.Write("hostile.ply", content);
  ExpectInputError([&] { ReadPlyMesh(path); }, path, 0, "face 1 has 0 vertices");
  // The cap itself: triangles for the faces declared, at most what the
  // bytes can hold.
  std::vector<std::int64_t> tris;
  ReserveTriangles(1000000, 1000013, 13, &tris);
  EXPECT_GE(tris.capacity(), 3u * 76924);
  EXPECT_LT(tris.capacity(), 3u * 76924 + 64);
  std::vector<std::int64_t> few;
  ReserveTriangles(10, 1000000, 13, &few);
  EXPECT_GE(few.capacity(), 30u);
  EXPECT_LT(few.capacity(), 64u);
  std::vector<std::int64_t> unknown;
  ReserveTriangles(1000000, -1, 13, &unknown);
  EXPECT_EQ(unknown.capacity(), 0u);
}

}  // namespace
}  // namespace invmap::io
