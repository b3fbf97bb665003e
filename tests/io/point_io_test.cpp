// Streaming point input (io/point_reader.h) in every format variant, and
// the trim output (io/trim_writer.h) that passes records through.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "io/input_error.h"
#include "io/npy.h"
#include "io/point_reader.h"
#include "io/trim_writer.h"
#include "tests/io/io_scratch.h"

namespace invmap::io {
namespace {

using scratch::ExpectInputError;
using scratch::Put;
using scratch::ReadAll;
using scratch::ScratchDir;

/// Everything a reader delivers, read in chunks of `chunkSize`.
struct AllPoints {
  int dim = 0;
  std::int64_t hint = 0;
  std::vector<double> xyz;
  std::vector<std::string> raw;  ///< One record per point.
  std::size_t chunks = 0;
};

AllPoints ReadAllPoints(const std::string& path, std::size_t chunkSize, const PointReadOptions& options = {}) {
  AllPoints all;
  const auto reader = OpenPointReader(path, options);
  all.dim = reader->dim();
  all.hint = reader->totalCountHint();
  PointChunk chunk;
  std::int64_t expectedFirst = 0;
  while (reader->ReadChunk(chunkSize, &chunk)) {
    EXPECT_EQ(chunk.firstIndex, expectedFirst);
    EXPECT_LE(chunk.count, chunkSize);
    EXPECT_EQ(chunk.xyz.size(), chunk.count * static_cast<std::size_t>(all.dim));
    all.xyz.insert(all.xyz.end(), chunk.xyz.begin(), chunk.xyz.end());
    if (options.keepRaw) {
      EXPECT_EQ(chunk.rawOffsets.size(), chunk.count + 1);
      EXPECT_EQ(chunk.rawOffsets.back(), chunk.raw.size());
      for (std::size_t i = 0; i < chunk.count; ++i) {
        all.raw.push_back(chunk.raw.substr(chunk.rawOffsets[i], chunk.rawOffsets[i + 1] - chunk.rawOffsets[i]));
      }
    }
    expectedFirst += static_cast<std::int64_t>(chunk.count);
    ++all.chunks;
  }
  EXPECT_EQ(chunk.count, 0u);
  EXPECT_FALSE(reader->ReadChunk(chunkSize, &chunk));  // stays at the end
  return all;
}

/// Reads `path` whole and in chunks of 1, 2 and 7 points; all must agree.
/// Returns the whole read.
AllPoints ReadChecked(const std::string& path, const PointReadOptions& options = {}) {
  const AllPoints whole = ReadAllPoints(path, 1u << 20, options);
  for (std::size_t chunkSize : {1u, 2u, 7u}) {
    SCOPED_TRACE("chunk size " + std::to_string(chunkSize));
    const AllPoints parts = ReadAllPoints(path, chunkSize, options);
    EXPECT_EQ(parts.dim, whole.dim);
    EXPECT_EQ(parts.raw, whole.raw);
    EXPECT_EQ(parts.xyz.size(), whole.xyz.size());
    if (parts.xyz.size() != whole.xyz.size()) continue;
    for (std::size_t i = 0; i < whole.xyz.size(); ++i) {
      // NaN inputs must stay NaN; everything else bit for bit.
      EXPECT_TRUE(parts.xyz[i] == whole.xyz[i] || (std::isnan(parts.xyz[i]) && std::isnan(whole.xyz[i]))) << i;
    }
  }
  return whole;
}

// ---------------------------------------------------------------------------
// Text

TEST(TextPoints, SeparatorsHeadersAndExtraColumns) {
  ScratchDir dir;
  struct Case {
    const char* name;
    const char* content;
    int dim;
    std::vector<double> xyz;
    const char* header;
  };
  const std::vector<Case> cases = {
      {"space.xyz", "1 2 3\n4 5 6\n", 3, {1, 2, 3, 4, 5, 6}, ""},
      {"comma.csv", "1,2,3\n4,5,6\n", 3, {1, 2, 3, 4, 5, 6}, ""},
      {"mixed.txt", " 1 ,\t2, 3 \n4\t5 6\n", 3, {1, 2, 3, 4, 5, 6}, ""},
      {"header.csv", "x,y,z\n1,2,3\n", 3, {1, 2, 3}, "x,y,z\n"},
      {"extra.csv",
       "x,y,z,intensity,label\n1,2,3,0.5,tree\n4,5,6,0.7,house\n",
       3,
       {1, 2, 3, 4, 5, 6},
       "x,y,z,intensity,label\n"},
      {"2d.xyz", "# x y\n1 2\n3 4\n", 2, {1, 2, 3, 4}, "# x y\n"},
      {"2dlabel.txt", "1 2 label\n3 4 other\n", 2, {1, 2, 3, 4}, ""},
      {"crlf.csv", "x,y,z\r\n1,2,3\r\n4,5,6", 3, {1, 2, 3, 4, 5, 6}, "x,y,z\r\n"},
      {"bom.csv",
       "\xEF\xBB\xBF"
       "1,2,3\n",
       3,
       {1, 2, 3},
       ""},
      {"blank.xyz", "\n  \n1 2 3\n\n4 5 6\n\n", 3, {1, 2, 3, 4, 5, 6}, ""},
      {"signs.xyz", "+1 -2 1e3\n-1.5E-2 .5 +.25\n", 3, {1, -2, 1000, -0.015, 0.5, 0.25}, ""},
      {"UPPER.XYZ", "1 2 3\n", 3, {1, 2, 3}, ""},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir.Write(c.name, c.content);
    const AllPoints all = ReadChecked(path);
    EXPECT_EQ(all.dim, c.dim);
    EXPECT_EQ(all.hint, -1);
    EXPECT_EQ(all.xyz, c.xyz);
    EXPECT_EQ(OpenPointReader(path)->layout().textHeader, c.header);
    EXPECT_EQ(OpenPointReader(path)->layout().format, PointFormat::Text);
  }
}

TEST(TextPoints, RawLinesAreVerbatim) {
  ScratchDir dir;
  const AllPoints all = ReadChecked(dir.Write("p.csv", "x,y,z,c\n1,2,3,red\r\n\n4,5,6,blue"));
  EXPECT_EQ(all.raw, (std::vector<std::string>{"1,2,3,red\r\n", "4,5,6,blue\n"}));
}

TEST(TextPoints, NonFiniteValuesAreRead) {
  ScratchDir dir;
  const AllPoints all = ReadChecked(dir.Write("p.xyz", "nan 0 0\n0 inf -Infinity\n"));
  EXPECT_TRUE(std::isnan(all.xyz[0]));
  EXPECT_EQ(all.xyz[4], std::numeric_limits<double>::infinity());
  EXPECT_EQ(all.xyz[5], -std::numeric_limits<double>::infinity());
}

TEST(TextPoints, ForcedDimension) {
  ScratchDir dir;
  const std::string path = dir.Write("p.xyz", "1 2 3 4\n5 6 7 8\n");
  EXPECT_EQ(ReadChecked(path).dim, 3);
  const AllPoints two = ReadChecked(path, PointReadOptions{2, true});
  EXPECT_EQ(two.dim, 2);
  EXPECT_EQ(two.xyz, (std::vector<double>{1, 2, 5, 6}));
  EXPECT_EQ(OpenPointReader(path, 2)->dim(), 2);
  const std::string flat = dir.Write("q.xyz", "1 2\n");
  ExpectInputError([&] { ReadAllPoints(flat, 10, PointReadOptions{3, true}); }, flat, 1, "expected 3 numbers, found 2");
  EXPECT_THROW(OpenPointReader(path, 4), std::invalid_argument);
}

TEST(TextPoints, WithoutRawRecords) {
  ScratchDir dir;
  const auto reader = OpenPointReader(dir.Write("p.xyz", "1 2 3\n"), PointReadOptions{0, false});
  PointChunk chunk;
  ASSERT_TRUE(reader->ReadChunk(10, &chunk));
  EXPECT_TRUE(chunk.raw.empty());
  EXPECT_TRUE(chunk.rawOffsets.empty());
}

TEST(TextPoints, RejectsBadInput) {
  ScratchDir dir;
  const auto expectBad = [&](const std::string& name, const std::string& content, std::int64_t line,
                             const std::string& part) {
    const std::string path = dir.Write(name, content);
    ExpectInputError([&] { ReadAllPoints(path, 4); }, path, line, part);
  };
  expectBad("empty.xyz", "", 0, "empty file");
  expectBad("blank.xyz", "\n\n \n", 0, "empty file");
  expectBad("header.csv", "x,y,z\n", 0, "no data lines");
  expectBad("twoheaders.csv", "x,y,z\nu,v,w\n1,2,3\n", 2, "expected at least 2 numbers");
  expectBad("one.xyz", "1\n2\n", 1, "expected at least 2 numbers");
  expectBad("word.xyz", "1 2 3\n4 5 6\n7 abc 9\n", 3, "column 2: 'abc' is not a number");
  expectBad("short.xyz", "1 2 3\n\n4 5\n", 3, "expected 3 numbers, found 2");
  expectBad("trailing.csv", "1,2,3\n4,5x,6\n", 2, "'5x' is not a number");
  expectBad("emptyfield.csv", "1,2,3\n4,,6\n", 2, "column 2: '' is not a number");
  expectBad("binary.xyz", std::string("\x01\x02\n\x00\x7f\n", 6), 2, "expected at least 2 numbers");
  // Old Mac line endings: the whole file is one line; say why.
  expectBad("mac.csv", "x,y,z\r1,2,3\r4,5,6\r", 1, "lines must end in \\n or \\r\\n, not in \\r alone");
  expectBad("mac.xyz", "1 2 3\r4 5 6\r", 1, "a carriage return inside the line");
  ExpectInputError([&] { OpenPointReader(dir.Path("missing.xyz")); }, dir.Path("missing.xyz"), 0, "no such file");
  const std::string sub = dir.Path("sub.xyz");
  std::filesystem::create_directory(sub);
  ExpectInputError([&] { OpenPointReader(sub); }, sub, 0, "is a directory");
  ExpectInputError([&] { OpenPointReader(dir.Write("p.e57", "x")); }, dir.Path("p.e57"), 0,
                   "unknown point file extension '.e57'");
}

// ---------------------------------------------------------------------------
// PLY

/// Writes a vertex element of `count` points with x, y, (z) of `type` plus
/// a uchar and a float attribute, in `format`, and a face element after it.
std::string PlyPoints(const std::string& format, const std::string& type, int dim, int count) {
  std::string header = "ply\nformat " + format + " 1.0\ncomment test points\nelement vertex " + std::to_string(count) +
                       "\nproperty " + type + " x\nproperty uchar red\nproperty " + type + " y\n";
  if (dim == 3) header += "property " + type + " z\n";
  header += "property float intensity\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const bool big = format == "binary_big_endian";
  std::string data;
  for (int i = 0; i < count; ++i) {
    const double coords[3] = {static_cast<double>(i), static_cast<double>(2 * i + 1), static_cast<double>(100 - i)};
    if (format == "ascii") {
      data += std::to_string(i) + " 7 " + std::to_string(2 * i + 1);
      if (dim == 3) data += " " + std::to_string(100 - i);
      data += " 0.5\n";
      continue;
    }
    const auto put = [&](double v) {
      if (type == "float") Put<float>(&data, static_cast<float>(v), big);
      if (type == "double") Put<double>(&data, v, big);
      if (type == "int") Put<std::int32_t>(&data, static_cast<std::int32_t>(v), big);
      if (type == "uchar") Put<std::uint8_t>(&data, static_cast<std::uint8_t>(v), big);
    };
    put(coords[0]);
    Put<std::uint8_t>(&data, 7, big);
    put(coords[1]);
    if (dim == 3) put(coords[2]);
    Put<float>(&data, 0.5f, big);
  }
  if (format == "ascii") {
    data += "3 0 1 2\n";
  } else {
    Put<std::uint8_t>(&data, 3, big);
    for (int v = 0; v < 3; ++v) Put<std::int32_t>(&data, v, big);
  }
  return header + data;
}

TEST(PlyPoints, EveryFormatAndCoordinateType) {
  ScratchDir dir;
  for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    for (const char* type : {"float", "double", "int", "uchar"}) {
      for (int dim : {2, 3}) {
        SCOPED_TRACE(std::string(format) + " " + type + " " + std::to_string(dim) + "D");
        const std::string path = dir.Write("p.ply", PlyPoints(format, type, dim, 9));
        const AllPoints all = ReadChecked(path);
        EXPECT_EQ(all.dim, dim);
        EXPECT_EQ(all.hint, 9);
        ASSERT_EQ(all.xyz.size(), static_cast<std::size_t>(9 * dim));
        for (int i = 0; i < 9; ++i) {
          EXPECT_EQ(all.xyz[static_cast<std::size_t>(i * dim)], i);
          EXPECT_EQ(all.xyz[static_cast<std::size_t>(i * dim + 1)], 2 * i + 1);
          if (dim == 3) {
            EXPECT_EQ(all.xyz[static_cast<std::size_t>(i * dim + 2)], 100 - i);
          }
        }
        // Raw records: the vertex data exactly (faces are not points).
        std::string records;
        for (const std::string& r : all.raw) records += r;
        const std::string file = ReadAll(path);
        const std::size_t start = file.find("end_header\n") + 11;
        EXPECT_EQ(file.compare(start, records.size(), records), 0);
        const auto reader = OpenPointReader(path);
        EXPECT_EQ(reader->layout().format, PointFormat::Ply);
        EXPECT_EQ(reader->layout().plyVertexElement, 0u);
        if (dim == 3) {
          EXPECT_EQ(OpenPointReader(path, 2)->dim(), 2);
        }
      }
    }
  }
}

TEST(PlyPoints, VertexElementAfterAnotherElement) {
  ScratchDir dir;
  std::string bytes =
      "ply\nformat binary_little_endian 1.0\nelement camera 1\nproperty double f\nelement vertex 2\n"
      "property float x\nproperty float y\nproperty float z\nend_header\n";
  Put<double>(&bytes, 35.0);
  for (float v : {1.f, 2.f, 3.f, 4.f, 5.f, 6.f}) Put<float>(&bytes, v);
  const AllPoints all = ReadChecked(dir.Write("p.ply", bytes));
  EXPECT_EQ(all.xyz, (std::vector<double>{1, 2, 3, 4, 5, 6}));
}

TEST(PlyPoints, RejectsBadInput) {
  ScratchDir dir;
  const auto expectBad = [&](const std::string& content, std::int64_t line, const std::string& part,
                             int forcedDim = 0) {
    const std::string path = dir.Write("bad.ply", content);
    ExpectInputError([&] { ReadAllPoints(path, 3, PointReadOptions{forcedDim, true}); }, path, line, part);
  };
  expectBad("ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n", 0,
            "no 'vertex' element");
  expectBad("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float z\nend_header\n1 2\n", 0,
            "no x or y property");
  expectBad("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n", 0,
            "dimension 3 requested", 3);
  expectBad(
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty list uchar float y\nend_header\n"
      "1 1 2\n",
      0, "is a list");
  expectBad(
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nend_header\n"
      "1 2\n3 4\n5 six\n",
      9, "'six' is not a number");
  // Binary data shorter than the header promises fails the size check;
  // ascii data is only known short when it runs out.
  std::string truncated = PlyPoints("binary_little_endian", "double", 3, 5);
  truncated.resize(truncated.size() - 20);
  expectBad(truncated, 0, "declares 5 'vertex' records");
  expectBad(
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nend_header\n"
      "1.0000 2.0000\n3.0000 4.0000\n",
      9, "the file ends in 'vertex' record 2 of 3");
  // A short ascii line, in a file too short for the records' full width.
  expectBad(
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "end_header\n0 0 0\n1 1\n1 2 3\n",
      9, "'vertex' record 1: too few values: none for property 'z'");
  std::string huge =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4294967295\nproperty float x\nproperty float y\n"
      "end_header\n";
  huge.resize(128, '\0');
  // Refused by the header's promise alone, before any record is read.
  expectBad(huge, 0, "declares 4294967295 'vertex' records");
  std::string hugeAscii =
      "ply\nformat ascii 1.0\nelement vertex 4294967295\nproperty float x\nproperty float y\nend_header\n";
  expectBad(hugeAscii + "1 2\n3 4\n", 0, "declares 4294967295 'vertex' records");
  expectBad("", 0, "empty file");
}

// ---------------------------------------------------------------------------
// npy

/// An npy file of `rows` x `columns` values i * 10 + c, dtype descr.
std::string Npy(const std::string& descr, std::int64_t rows, int columns, int version = 1,
                const std::string& fortran = "False") {
  std::string dict = "{'descr': '" + descr + "', 'fortran_order': " + fortran + ", 'shape': (" + std::to_string(rows) +
                     ", " + std::to_string(columns) + "), }";
  const std::size_t prefix = version == 1 ? 10 : 12;
  while ((prefix + dict.size() + 1) % 64 != 0) dict += ' ';
  dict += '\n';
  std::string bytes = std::string("\x93NUMPY", 6);
  bytes.push_back(static_cast<char>(version));
  bytes.push_back('\0');
  if (version == 1) {
    Put<std::uint16_t>(&bytes, static_cast<std::uint16_t>(dict.size()));
  } else {
    Put<std::uint32_t>(&bytes, static_cast<std::uint32_t>(dict.size()));
  }
  bytes += dict;
  const bool big = descr[0] == '>';
  for (std::int64_t i = 0; i < rows; ++i) {
    for (int c = 0; c < columns; ++c) {
      const double v = static_cast<double>(i) * 10 + c + 0.25;
      if (descr[2] == '8') {
        Put<double>(&bytes, v, big);
      } else {
        Put<float>(&bytes, static_cast<float>(v), big);
      }
    }
  }
  return bytes;
}

TEST(NpyPoints, FloatTypesByteOrdersAndShapes) {
  ScratchDir dir;
  for (const char* descr : {"<f8", ">f8", "<f4", ">f4", "=f8"}) {
    for (int columns : {2, 3}) {
      for (int version : {1, 2}) {
        SCOPED_TRACE(std::string(descr) + " columns " + std::to_string(columns) + " v" + std::to_string(version));
        const std::string path = dir.Write("p.npy", Npy(descr, 11, columns, version));
        const AllPoints all = ReadChecked(path);
        EXPECT_EQ(all.dim, columns);
        EXPECT_EQ(all.hint, 11);
        ASSERT_EQ(all.xyz.size(), static_cast<std::size_t>(11 * columns));
        for (int i = 0; i < 11; ++i) {
          for (int c = 0; c < columns; ++c)
            EXPECT_EQ(all.xyz[static_cast<std::size_t>(i * columns + c)], i * 10 + c + 0.25);
        }
        ASSERT_EQ(all.raw.size(), 11u);
        EXPECT_EQ(all.raw[0].size(), static_cast<std::size_t>(columns * (descr[2] - '0')));
        const auto reader = OpenPointReader(path);
        EXPECT_EQ(reader->layout().npyDescr, descr);
        EXPECT_EQ(reader->layout().npyColumns, columns);
      }
    }
  }
  // Three columns read as 2D: the first two.
  const AllPoints two = ReadChecked(dir.Write("q.npy", Npy("<f8", 2, 3)), PointReadOptions{2, true});
  EXPECT_EQ(two.xyz, (std::vector<double>{0.25, 1.25, 10.25, 11.25}));
  // An empty array is valid: no points.
  EXPECT_TRUE(ReadChecked(dir.Write("e.npy", Npy("<f8", 0, 3))).xyz.empty());
}

TEST(NpyPoints, RejectsBadInput) {
  ScratchDir dir;
  const auto expectBad = [&](const std::string& content, const std::string& part, int forcedDim = 0) {
    const std::string path = dir.Write("bad.npy", content);
    ExpectInputError([&] { ReadAllPoints(path, 3, PointReadOptions{forcedDim, true}); }, path, 0, part);
  };
  expectBad(Npy("<f8", 4, 3, 1, "True"), "fortran_order is True");
  expectBad(Npy("<i4", 4, 3), "unsupported dtype '<i4'");
  expectBad(Npy("<f2", 4, 3), "unsupported dtype '<f2'");
  expectBad(Npy("<f8", 4, 4), "shape (4, 4) is not (N, 2) or (N, 3)");
  expectBad(Npy("<f8", 4, 2), "dimension 3 requested", 3);
  std::string oneD = Npy("<f8", 4, 3);
  oneD.replace(oneD.find("(4, 3)"), 6, "(12,) ");
  expectBad(oneD, "shape (12) is not");
  std::string truncated = Npy("<f8", 4, 3);
  truncated.resize(truncated.size() - 8);
  expectBad(truncated, "does not match the 88 data bytes");
  expectBad(Npy("<f8", 4, 3) + "extra", "does not match");
  // A shape of 2^62 rows in a small file: refused without allocating.
  std::string huge = Npy("<f8", 0, 3);
  huge.replace(huge.find("(0, 3)"), 6, "(4611686018427387904, 3)");
  huge.resize(128, ' ');
  huge.back() = '\n';
  huge[8] = static_cast<char>(118);
  expectBad(huge, "(4611686018427387904, 3) of float64 does not match");
  expectBad("", "empty file");
  expectBad("\x93NUMP", "not a npy file");
  expectBad(std::string("\x93NUMPY\x09\x00\x10\x00", 10), "unsupported npy format version 9");
  expectBad(std::string("\x93NUMPY\x01\x00\xff\xff", 10) + "{", "truncated or oversized npy header");
  std::string noShape = Npy("<f8", 1, 3);
  noShape.replace(noShape.find("'shape'"), 7, "'shapf'");
  expectBad(noShape, "unexpected key 'shapf'");
  std::string structured = Npy("<f8", 1, 3);
  structured.replace(structured.find("'<f8'"), 5, "[('x',");
  expectBad(structured, "structured dtypes are not supported");
}

// ---------------------------------------------------------------------------
// Trim

/// Reads `input` with raw records and writes every point whose index
/// satisfies keep(i) to `output`.
template <class Keep>
std::int64_t Trim(const std::string& input, const std::string& output, Keep keep, std::size_t chunkSize = 3) {
  const auto reader = OpenPointReader(input);
  TrimWriter writer(output, reader->layout());
  PointChunk chunk;
  std::vector<unsigned char> flags;
  while (reader->ReadChunk(chunkSize, &chunk)) {
    flags.assign(chunk.count, 0);
    for (std::size_t i = 0; i < chunk.count; ++i) flags[i] = keep(chunk.firstIndex + static_cast<std::int64_t>(i));
    writer.WriteChunk(chunk, flags.data());
  }
  writer.Finish();
  return writer.written();
}

bool IsEven(std::int64_t i) { return i % 2 == 0; }

TEST(TrimWriter, TextKeepsHeaderAndLinesVerbatim) {
  ScratchDir dir;
  const std::string input = dir.Write("in.csv", "x,y,z,label\r\n0,0,0,a\r\n1,1,1,b\n\n2,2,2,c\n3,3,3,d");
  EXPECT_EQ(Trim(input, dir.Path("out.csv"), IsEven), 2);
  EXPECT_EQ(ReadAll(dir.Path("out.csv")), "x,y,z,label\r\n0,0,0,a\r\n2,2,2,c\n");
  // Another text extension is fine; no header stays no header.
  const std::string plain = dir.Write("in.xyz", "0 0 0\n1 1 1\n");
  EXPECT_EQ(Trim(plain, dir.Path("out.txt"), [](std::int64_t i) { return i == 1; }), 1);
  EXPECT_EQ(ReadAll(dir.Path("out.txt")), "1 1 1\n");
  // Nothing kept: the header alone.
  Trim(input, dir.Path("none.csv"), [](std::int64_t) { return false; });
  EXPECT_EQ(ReadAll(dir.Path("none.csv")), "x,y,z,label\r\n");
}

TEST(TrimWriter, PlyPatchesTheCountAndDropsOtherElements) {
  ScratchDir dir;
  for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    SCOPED_TRACE(format);
    const std::string input = dir.Write("in.ply", PlyPoints(format, "double", 3, 10));
    const std::string output = dir.Path("out.ply");
    EXPECT_EQ(Trim(input, output, IsEven), 5);
    const std::string text = ReadAll(output);
    const std::string header = text.substr(0, text.find("end_header\n") + 11);
    EXPECT_EQ(header, std::string("ply\nformat ") + format +
                          " 1.0\ncomment test points\nelement vertex 5\ncomment            \nproperty double x\n"
                          "property uchar red\nproperty double y\nproperty double z\nproperty float intensity\n"
                          "end_header\n");
    // Read back: the even points with their attributes.
    PlyReader reader(output);
    PlyRecord record;
    for (int i = 0; i < 10; i += 2) {
      ASSERT_TRUE(reader.ReadRecord(&record));
      EXPECT_EQ(record.Scalar(0), i);
      EXPECT_EQ(record.Scalar(1), 7);
      EXPECT_EQ(record.Scalar(2), 2 * i + 1);
      EXPECT_EQ(record.Scalar(3), 100 - i);
      EXPECT_EQ(record.Scalar(4), 0.5);
    }
    EXPECT_FALSE(reader.ReadRecord(&record));
    // Nothing after the records (29 bytes each in binary).
    if (format[0] != 'a') {
      EXPECT_EQ(text.size(), header.size() + 5 * 29);
    }
  }
}

TEST(TrimWriter, NpyKeepsDtypeAndRows) {
  ScratchDir dir;
  for (const char* descr : {"<f4", ">f8"}) {
    SCOPED_TRACE(descr);
    const std::string input = dir.Write("in.npy", Npy(descr, 7, 2));
    const std::string output = dir.Path("out.npy");
    EXPECT_EQ(Trim(input, output, IsEven), 4);
    const std::string bytes = ReadAll(output);
    EXPECT_EQ(bytes.substr(0, kNpyFixedHeaderBytes), FixedNpyHeader(descr, 4, 2));
    const AllPoints all = ReadChecked(output);
    EXPECT_EQ(all.xyz, (std::vector<double>{0.25, 1.25, 20.25, 21.25, 40.25, 41.25, 60.25, 61.25}));
  }
}

TEST(TrimWriter, RejectsAnotherFormatOrMissingRawRecords) {
  ScratchDir dir;
  const std::string input = dir.Write("in.ply", PlyPoints("ascii", "float", 3, 2));
  const auto reader = OpenPointReader(input);
  ExpectInputError([&] { TrimWriter writer(dir.Path("out.csv"), reader->layout()); }, dir.Path("out.csv"), 0,
                   "trim writes the input's format, PLY", InputError::Kind::Output);
  ExpectInputError([&] { TrimWriter writer(dir.Path("out.e57"), reader->layout()); }, dir.Path("out.e57"), 0,
                   "unknown point file extension", InputError::Kind::Output);
  const auto noRaw = OpenPointReader(input, PointReadOptions{0, false});
  PointChunk chunk;
  ASSERT_TRUE(noRaw->ReadChunk(10, &chunk));
  TrimWriter writer(dir.Path("out.ply"), noRaw->layout());
  const unsigned char keep[2] = {1, 1};
  EXPECT_THROW(writer.WriteChunk(chunk, keep), std::invalid_argument);
}

TEST(TrimWriter, OutputAppearsOnlyOnFinish) {
  ScratchDir dir;
  const std::string input = dir.Write("in.xyz", "1 2 3\n4 5 6\n");
  const std::string output = dir.Write("out.xyz", "old content\n");
  const std::size_t entries = dir.EntryCount();
  {
    const auto reader = OpenPointReader(input);
    TrimWriter writer(output, reader->layout());
    PointChunk chunk;
    reader->ReadChunk(10, &chunk);
    const unsigned char keep[2] = {1, 1};
    writer.WriteChunk(chunk, keep);
    EXPECT_EQ(ReadAll(output), "old content\n");
    // No Finish: the old file stays and the temporary file goes.
  }
  EXPECT_EQ(ReadAll(output), "old content\n");
  EXPECT_EQ(dir.EntryCount(), entries);
  Trim(input, output, [](std::int64_t) { return true; });
  EXPECT_EQ(ReadAll(output), "1 2 3\n4 5 6\n");
  EXPECT_EQ(dir.EntryCount(), entries);
}

}  // namespace
}  // namespace invmap::io
