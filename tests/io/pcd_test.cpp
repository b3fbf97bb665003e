// The PCD point reader and trim's PCD output: files of every encoding from
// an independent writer (tests/support/pcd_writer) and from the Point Cloud
// Library's own writer (its converter, pcl_convert_pcd_ascii_binary), trimmed
// files read back by PCL, the streaming LZF decoder against liblzf, and bad
// files refused naming the file and line.
#include <gtest/gtest.h>
#include <lzf.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "io/input_error.h"
#include "io/lzf_stream.h"
#include "io/point_reader.h"
#include "io/trim_writer.h"
#include "tests/io/io_scratch.h"
#include "tests/support/pcd_writer.h"

namespace invmap::io {
namespace {

using scratch::ExpectInputError;
using scratch::ReadAll;
using scratch::ScratchDir;
using testing::PcdTestCloud;

const char* const kEncodings[] = {"ascii", "binary", "binary_compressed"};

struct ReadBack {
  std::vector<double> xyz;
  std::vector<std::string> records;
  int dim = 0;
};

ReadBack ReadEverything(const std::string& path, std::size_t chunkPoints, bool keepRaw = true) {
  PointReadOptions options;
  options.keepRaw = keepRaw;
  auto reader = OpenPointReader(path, options);
  ReadBack back;
  back.dim = reader->dim();
  PointChunk chunk;
  while (reader->ReadChunk(chunkPoints, &chunk)) {
    back.xyz.insert(back.xyz.end(), chunk.xyz.begin(), chunk.xyz.end());
    for (std::size_t i = 0; keepRaw && i < chunk.count; ++i) {
      back.records.push_back(chunk.raw.substr(chunk.rawOffsets[i], chunk.rawOffsets[i + 1] - chunk.rawOffsets[i]));
    }
  }
  return back;
}

void Trim(const std::string& input, const std::string& output, const std::vector<unsigned char>& keep,
          std::size_t chunkPoints) {
  auto reader = OpenPointReader(input, PointReadOptions{});
  TrimWriter writer(output, reader->layout());
  PointChunk chunk;
  while (reader->ReadChunk(chunkPoints, &chunk)) writer.WriteChunk(chunk, keep.data() + chunk.firstIndex);
  writer.Finish();
}

/// The coordinates of a cloud's points, as the reader should give them.
std::vector<double> Coordinates(const PcdTestCloud& cloud) {
  std::vector<double> xyz;
  for (const std::vector<double>& point : cloud.points) {
    for (const char* name : {"x", "y", "z"}) {
      std::size_t value = 0;
      for (const testing::PcdTestField& f : cloud.fields) {
        if (f.name == name) {
          xyz.push_back(point[value]);
          break;
        }
        value += f.count;
      }
    }
  }
  return xyz;
}

/// The cloud without its points' values of "_" fields.
PcdTestCloud WithoutPadding(const PcdTestCloud& cloud) {
  PcdTestCloud out;
  std::vector<bool> keepValue;
  for (const testing::PcdTestField& f : cloud.fields) {
    if (f.name != "_") out.fields.push_back(f);
    keepValue.insert(keepValue.end(), f.count, f.name != "_");
  }
  for (const std::vector<double>& point : cloud.points) {
    std::vector<double> values;
    for (std::size_t v = 0; v < point.size(); ++v) {
      if (keepValue[v]) values.push_back(point[v]);
    }
    out.points.push_back(values);
  }
  return out;
}

/// The data lines (after DATA) or bytes of a PCD file.
std::string DataPart(const std::string& file) {
  const std::size_t data = file.find("\nDATA ");
  return file.substr(file.find('\n', data + 1) + 1);
}

/// The records the reader should give for `cloud` written in `encoding`.
std::vector<std::string> ExpectedRecords(const PcdTestCloud& cloud, const std::string& encoding) {
  std::vector<std::string> records;
  for (const std::vector<double>& point : cloud.points) {
    PcdTestCloud one = encoding == "binary_compressed" ? WithoutPadding(cloud) : cloud;
    one.points = {encoding == "binary_compressed" ? WithoutPadding({cloud.fields, {point}, 0, 1}).points[0] : point};
    one.width = 0;
    one.height = 1;
    records.push_back(DataPart(testing::WritePcd(one, encoding == "ascii" ? "ascii" : "binary")));
  }
  return records;
}

/// The uncompressed data of a binary_compressed file (liblzf decompresses).
std::string Decompressed(const std::string& file) {
  const std::string data = DataPart(file);
  std::uint32_t sizes[2];
  std::memcpy(sizes, data.data(), 8);
  std::string out(sizes[1], '\0');
  if (sizes[1] > 0) {
    EXPECT_EQ(lzf_decompress(data.data() + 8, sizes[0], out.data(), sizes[1]), sizes[1]);
  }
  return out;
}

/// A header line's value ("WIDTH 12" -> "12"), "" when absent.
std::string HeaderValue(const std::string& file, const std::string& keyword) {
  std::istringstream in(file);
  std::string line;
  while (std::getline(in, line) && line.rfind("DATA", 0) != 0) {
    if (line.rfind(keyword + " ", 0) == 0) return line.substr(keyword.size() + 1);
  }
  return "";
}

TEST(PcdTest, LzfStreamDecodesWhatLiblzfCompressesInAnyPieces) {
  ScratchDir dir;
  std::mt19937_64 rng(1);
  // Compressible data with long and overlapping repeats, more than the
  // 8 KiB window and many input blocks long.
  std::string data;
  while (data.size() < 300000) {
    if (data.size() > 10 && rng() % 3 == 0) {
      const std::size_t back = 1 + rng() % std::min<std::size_t>(data.size(), 9000);
      const std::size_t length = 1 + rng() % 400;
      for (std::size_t i = 0; i < length; ++i) data.push_back(data[data.size() - back]);
    } else {
      data.push_back(static_cast<char>(rng() % 7));
    }
  }
  std::string packed(data.size() * 2, '\0');
  const unsigned int n = lzf_compress(data.data(), static_cast<unsigned int>(data.size()), packed.data(),
                                      static_cast<unsigned int>(packed.size()));
  ASSERT_GT(n, 0u);
  packed.resize(n);
  const std::string path = dir.Write("data.lzf", "prefix" + packed + "suffix");
  auto file = std::make_shared<const PositionalFile>(path);
  LzfStream stream(file, 6, n, data.size());
  std::string out;
  std::unique_ptr<LzfStream> snapshot;
  std::size_t snapshotAt = 0;
  while (out.size() < data.size()) {
    const std::size_t piece = std::min<std::size_t>(data.size() - out.size(), 1 + rng() % 5000);
    if (!snapshot && out.size() > 100000) {
      snapshot = std::make_unique<LzfStream>(stream);
      snapshotAt = out.size();
    }
    std::string buffer(piece, '\0');
    stream.Read(buffer.data(), piece);
    out += buffer;
  }
  EXPECT_TRUE(out == data);
  stream.ExpectEnd();
  // A copy continues independently from where it was taken.
  std::string rest(data.size() - snapshotAt, '\0');
  snapshot->Read(rest.data(), rest.size());
  EXPECT_TRUE(rest == data.substr(snapshotAt));
  // Declared sizes that do not match are errors naming the file.
  LzfStream longer(file, 6, n, data.size() + 1);
  longer.Skip(data.size());
  ExpectInputError([&] { longer.ExpectEnd(); }, path, 0, "the data ends after 300");
  LzfStream shorter(file, 6, n, data.size() - 1);
  ExpectInputError(
      [&] {
        shorter.Skip(data.size() - 1);
        shorter.ExpectEnd();
      },
      path, 0, "decompresses to more than");
  // A reference before the first byte, and a literal run cut off.
  const std::string bad = dir.Write("bad.lzf", std::string("\x20\x00", 2) + std::string("\x05" "ab", 3));
  auto badFile = std::make_shared<const PositionalFile>(bad);
  LzfStream reference(badFile, 0, 2, 10);
  ExpectInputError([&] { reference.Skip(1); }, bad, 0, "a back-reference reaches 1 bytes back from byte 0");
  LzfStream literal(badFile, 2, 3, 10);
  ExpectInputError([&] { literal.Skip(1); }, bad, 0, "a literal run of 6 bytes is cut off");
}

TEST(PcdTest, EveryEncodingAndCoordinateTypeReadsTheWrittenValues) {
  ScratchDir dir;
  std::mt19937_64 rng(2);
  const std::pair<char, std::size_t> types[] = {{'F', 4}, {'F', 8}, {'I', 2}, {'U', 4}, {'I', 8}, {'U', 1}};
  for (const auto& [type, size] : types) {
    for (const bool padding : {false, true}) {
      const PcdTestCloud cloud = testing::RandomPcdCloud(301, type, size, padding, &rng);
      for (const char* encoding : kEncodings) {
        SCOPED_TRACE(std::string(encoding) + " " + type + std::to_string(size) + (padding ? " with _" : ""));
        const std::string path = dir.Write("in.pcd", testing::WritePcd(cloud, encoding));
        const ReadBack back = ReadEverything(path, 41);
        EXPECT_EQ(back.dim, 3);
        ASSERT_EQ(back.xyz, Coordinates(cloud));
        EXPECT_EQ(back.records, ExpectedRecords(cloud, encoding));
        // Without raw records (invert) the coordinates are the same.
        EXPECT_EQ(ReadEverything(path, 1000, false).xyz, back.xyz);
      }
    }
  }
}

TEST(PcdTest, NanAndInfinityAreReadAsSuch) {
  ScratchDir dir;
  PcdTestCloud cloud;
  cloud.fields = {{"x", 'F', 4, 1}, {"y", 'F', 8, 1}, {"z", 'F', 4, 1}};
  cloud.points = {{1, 2, 3}, {std::nan(""), 0, 0}, {0, INFINITY, -INFINITY}};
  for (const char* encoding : kEncodings) {
    const ReadBack back = ReadEverything(dir.Write("nan.pcd", testing::WritePcd(cloud, encoding)), 10);
    ASSERT_EQ(back.xyz.size(), 9u) << encoding;
    EXPECT_TRUE(std::isnan(back.xyz[3])) << encoding;
    EXPECT_EQ(back.xyz[7], INFINITY) << encoding;
    EXPECT_EQ(back.xyz[8], -INFINITY) << encoding;
  }
}

TEST(PcdTest, TwoDimensionalCloudsHaveNoZ) {
  ScratchDir dir;
  PcdTestCloud cloud;
  cloud.fields = {{"y", 'F', 4, 1}, {"x", 'F', 4, 1}, {"w", 'U', 1, 1}};
  cloud.points = {{1, 2, 3}, {4, 5, 6}};
  const std::string path = dir.Write("flat.pcd", testing::WritePcd(cloud, "binary"));
  const ReadBack back = ReadEverything(path, 10);
  EXPECT_EQ(back.dim, 2);
  EXPECT_EQ(back.xyz, (std::vector<double>{2, 1, 5, 4}));
  PointReadOptions options;
  options.forcedDim = 3;
  ExpectInputError([&] { OpenPointReader(path, options); }, path, 0, "no z");
}

TEST(PcdTest, TrimKeepsTheEncodingAndEveryFieldOfTheKeptPoints) {
  ScratchDir dir;
  std::mt19937_64 rng(3);
  for (const bool padding : {false, true}) {
    PcdTestCloud cloud = testing::RandomPcdCloud(600, 'F', 4, padding, &rng);
    cloud.width = 30;  // organized: 30 x 20
    cloud.height = 20;
    std::vector<unsigned char> keep(cloud.points.size());
    PcdTestCloud kept = cloud;
    kept.points.clear();
    kept.width = 0;
    kept.height = 1;
    for (std::size_t i = 0; i < keep.size(); ++i) {
      keep[i] = rng() % 3 == 0;
      if (keep[i]) kept.points.push_back(cloud.points[i]);
    }
    for (const char* encoding : kEncodings) {
      SCOPED_TRACE(std::string(encoding) + (padding ? " with _" : ""));
      const std::string input = dir.Write("in.pcd", testing::WritePcd(cloud, encoding));
      Trim(input, dir.Path("out.pcd"), keep, 97);
      const std::string out = ReadAll(dir.Path("out.pcd"));
      const std::string count = std::to_string(kept.points.size());
      EXPECT_EQ(HeaderValue(out, "WIDTH"), count);
      EXPECT_EQ(HeaderValue(out, "HEIGHT"), "1");
      EXPECT_EQ(HeaderValue(out, "POINTS"), count);
      EXPECT_EQ(HeaderValue(out, "FIELDS"), HeaderValue(ReadAll(input), "FIELDS"));
      const std::string expected = testing::WritePcd(kept, encoding);
      if (std::string(encoding) == "binary_compressed") {
        // The kept values field after field, as PCL lays them out.
        EXPECT_TRUE(Decompressed(out) == Decompressed(expected));
      } else {
        EXPECT_TRUE(DataPart(out) == DataPart(expected));
      }
      const ReadBack back = ReadEverything(dir.Path("out.pcd"), 50);
      EXPECT_EQ(back.xyz, Coordinates(kept));
      EXPECT_EQ(back.records, ExpectedRecords(kept, encoding));
      // Trimming the trimmed file again keeps it as it is (the count's
      // padding is not repeated).
      Trim(dir.Path("out.pcd"), dir.Path("again.pcd"), std::vector<unsigned char>(kept.points.size(), 1), 1000);
      EXPECT_TRUE(ReadAll(dir.Path("again.pcd")) == out);
    }
  }
}

/// Runs PCL's converter: `input` to `output` in `encoding` (0 ascii, 1
/// binary, 2 binary_compressed; ascii with 17 digits). PCL's reader reads
/// the input, its writer writes the output.
void PclConvert(const std::string& input, const std::string& output, int encoding) {
  const std::string tool = INVMAP_PCL_CONVERT;
  ASSERT_FALSE(tool.empty()) << "pcl_convert_pcd_ascii_binary (Debian's pcl-tools) is missing: run scripts/setup.sh";
  const std::string command = tool + " " + input + " " + output + " " + std::to_string(encoding) +
                              (encoding == 0 ? " 17" : "") + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  ASSERT_FALSE(ReadAll(output).empty()) << "PCL wrote nothing: " << command;
}

TEST(PcdTest, FilesPclWritesAreReadAndFilesTrimWritesAreReadByPcl) {
  ScratchDir dir;
  std::mt19937_64 rng(4);
  PcdTestCloud cloud = testing::RandomPcdCloud(500, 'F', 4, false, &rng);
  cloud.fields.push_back({"rgb", 'F', 4, 1});  // PCL writes rgb as U in ascii
  for (auto& point : cloud.points) point.push_back(1.0);
  cloud.points[17][0] = std::nan("");  // PCL writes NaN as "nan"
  const std::string source = dir.Write("source.pcd", testing::WritePcd(cloud, "ascii"));
  std::vector<unsigned char> keep(cloud.points.size());
  for (auto& k : keep) k = rng() % 2;
  for (int encoding = 0; encoding <= 2; ++encoding) {
    SCOPED_TRACE(kEncodings[encoding]);
    const std::string pcl = dir.Path("pcl_" + std::to_string(encoding) + ".pcd");
    PclConvert(source, pcl, encoding);
    ASSERT_NE(ReadAll(pcl).find(std::string("DATA ") + kEncodings[encoding]), std::string::npos);
    const ReadBack back = ReadEverything(pcl, 64);
    const std::vector<double> expected = Coordinates(cloud);
    ASSERT_EQ(back.xyz.size(), expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i) {
      if (std::isnan(expected[i])) {
        EXPECT_TRUE(std::isnan(back.xyz[i]));
      } else {
        EXPECT_EQ(back.xyz[i], expected[i]) << "value " << i;
      }
    }
    // PCL reads the trimmed file as the kept rows of what it reads from
    // the input: both written out by PCL as ascii and compared line by line.
    Trim(pcl, dir.Path("trimmed.pcd"), keep, 64);
    PclConvert(dir.Path("trimmed.pcd"), dir.Path("trimmed_ascii.pcd"), 0);
    PclConvert(pcl, dir.Path("input_ascii.pcd"), 0);
    std::istringstream all(DataPart(ReadAll(dir.Path("input_ascii.pcd"))));
    std::string line;
    std::string keptLines;
    for (std::size_t i = 0; std::getline(all, line); ++i) {
      if (keep[i]) keptLines += line + "\n";
    }
    const std::string trimmedAscii = ReadAll(dir.Path("trimmed_ascii.pcd"));
    EXPECT_TRUE(DataPart(trimmedAscii) == keptLines);
    std::size_t keptCount = 0;
    for (unsigned char k : keep) keptCount += k;
    EXPECT_EQ(HeaderValue(trimmedAscii, "WIDTH"), std::to_string(keptCount));
    EXPECT_EQ(HeaderValue(trimmedAscii, "POINTS"), std::to_string(keptCount));
  }
}

TEST(PcdTest, BadFilesAreRefusedNamingTheFileAndLine) {
  ScratchDir dir;
  const std::string header =
      "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\n"
      "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\n";
  const auto expectRefused = [&](const std::string& bytes, std::int64_t line, const std::string& part) {
    const std::string path = dir.Write("bad.pcd", bytes);
    SCOPED_TRACE(part);
    ExpectInputError([&] { ReadEverything(path, 100); }, path, line, part);
  };
  expectRefused("", 0, "empty file");
  expectRefused("# only a comment\n", 1, "the header has no DATA line");
  expectRefused("VERSION 0.7\nFIELDS x y\nSIZE 4 4\nTYPE F F\nWIDTH 1\nWEIGHT 3\nDATA ascii\n1 2\n", 6,
                "unknown header line 'WEIGHT'");
  expectRefused("SIZE 4\nDATA ascii\n", 1, "SIZE before FIELDS");
  expectRefused("FIELDS x y\nSIZE 4\nDATA ascii\n", 2, "SIZE has 1 entries for 2 fields");
  expectRefused("FIELDS x y\nSIZE 4 4\nTYPE F X\nDATA ascii\n", 3, "field 'y': TYPE 'X' is not I, U or F");
  expectRefused("FIELDS x y\nSIZE 4 2\nTYPE F F\nWIDTH 1\nDATA ascii\n1 2\n", 3, "field 'y': TYPE F of SIZE 2");
  expectRefused("FIELDS x y\nSIZE 4 4\nTYPE F F\nCOUNT 1 0\nDATA ascii\n", 4, "field 'y': COUNT '0'");
  expectRefused("FIELDS x w\nSIZE 4 4\nTYPE F F\nWIDTH 1\nDATA ascii\n1 2\n", 1, "no x or no y");
  expectRefused("FIELDS x y x\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n1 2 3\n", 1, "two fields named 'x'");
  expectRefused("FIELDS x y\nSIZE 4 4\nTYPE F F\nWIDTH 2\nHEIGHT 2\nPOINTS 3\nDATA ascii\n", 7,
                "WIDTH (2) x HEIGHT (2) is not POINTS (3)");
  expectRefused("FIELDS x y\nSIZE 4 4\nTYPE F F\nWIDTH 1\nDATA text\n", 5, "unknown DATA encoding 'text'");
  expectRefused("FIELDS x y\nSIZE 4 4\nWIDTH 1\nDATA ascii\n", 4, "no TYPE line");
  expectRefused("FIELDS x y\nFIELDS x y\n", 2, "a second FIELDS line");
  // Ascii data: counts of values, numbers, lines.
  expectRefused(header + "DATA ascii\n1 2 3\n4 5\n", 13, "expected 3 values (3 fields), found 2");
  expectRefused(header + "DATA ascii\n1 2 3\n4 5 6 7\n", 13, "found more");
  expectRefused(header + "DATA ascii\n1 2 3\n4 five 6\n", 13, "field 'y': 'five' is not a number");
  expectRefused(header + "DATA ascii\n1 2 3\n", 12, "the file ends after 1 of its 2 points");
  expectRefused(header + "DATA ascii\n1 2 3\n4 5 6\n\n7 8 9\n", 15, "more points than the header's POINTS (2)");
  // Binary: a header claiming more points than the file holds is refused
  // before anything is read or allocated.
  std::string big = header;
  big.replace(big.find("WIDTH 2"), 7, "WIDTH 1000000000000000");
  big.replace(big.find("POINTS 2"), 8, "POINTS 1000000000000000");
  expectRefused(big + "DATA binary\n" + std::string(24, '\0'), 0, "POINTS 1000000000000000 of 12 bytes do not fit");
  expectRefused(header + "DATA binary\n" + std::string(20, '\0'), 0, "POINTS 2 of 12 bytes do not fit");
  // Binary_compressed: sizes that disagree, data past the end, bad LZF.
  PcdTestCloud cloud;
  cloud.fields = {{"x", 'F', 4, 1}, {"y", 'F', 4, 1}, {"z", 'F', 4, 1}};
  for (int i = 0; i < 200; ++i) cloud.points.push_back({i * 0.5, 1.0, 2.0});
  const std::string good = testing::WritePcd(cloud, "binary_compressed");
  const std::size_t sizesAt = good.size() - DataPart(good).size();
  std::string bytes = good;
  std::uint32_t value = 2399;
  std::memcpy(bytes.data() + sizesAt + 4, &value, 4);
  expectRefused(bytes, 0, "holds 2399 bytes, not POINTS (200) x 12 bytes per point");
  bytes = good;
  value = 1000000;
  std::memcpy(bytes.data() + sizesAt, &value, 4);
  expectRefused(bytes, 0, "run past the end of the file");
  bytes = good;
  bytes[sizesAt + 8] = '\x3f';  // a back-reference as the first token
  expectRefused(bytes, 0, "binary_compressed data, compressed byte");
  expectRefused(good.substr(0, sizesAt + 5), 0, "the file ends before the binary_compressed sizes");
}

}  // namespace
}  // namespace invmap::io
