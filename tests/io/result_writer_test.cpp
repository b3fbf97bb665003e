// Result files (io/result_writer.h): the exact CSV, PLY and npy layouts of
// docs/formats.md section 5, streaming in chunks, colours, and the rule that an
// output is complete or absent.
#include "io/result_writer.h"

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <array>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "io/file_io.h"
#include "io/input_error.h"
#include "io/npy.h"
#include "io/ply.h"
#include "tests/io/io_scratch.h"

namespace invmap::io {
namespace {

using scratch::ExpectInputError;
using scratch::ReadAll;
using scratch::ScratchDir;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

/// A small batch: a found point with an unused w, a found point with all
/// three parameters, a point not found and an invalid one.
struct Batch {
  std::vector<double> points;
  Results results;
};

Batch MakeBatch(int dim) {
  Batch batch;
  Results& r = batch.results;
  r.status = {Status::Found, Status::Found, Status::None, Status::Invalid};
  r.patch = {1, 0, -1, -1};
  r.cell = {42, 7, -1, -1};
  r.params = {0.5, 0.25, kNan, 0.1, 1.0 / 3, 2e-300, kNan, kNan, kNan, kNan, kNan, kNan};
  r.closest = {1, 2, dim == 3 ? 3.0 : 0.0, -0.5, 1e20, dim == 3 ? 0.2 : 0.0, kNan, kNan, kNan, kNan, kNan, kNan};
  r.distance = {0.125, 0.30000000000000004, kNan, kNan};
  r.iterations = {3, 4, 0, 0};
  const double query[4][3] = {{1, 2, 3.125}, {-0.5, 1e20, 0.5}, {9, 9, 9}, {kNan, 0, 0}};
  for (const auto& q : query) batch.points.insert(batch.points.end(), q, q + dim);
  return batch;
}

/// Writes `batch` to `path` in chunks of `chunkSize` rows and finishes.
void WriteBatch(const std::string& path, int dim, const Batch& batch, std::size_t chunkSize = 4,
                const ResultWriteOptions& options = {}) {
  const auto writer = OpenResultWriter(path, dim, options);
  const std::size_t n = batch.results.status.size();
  for (std::size_t first = 0; first < n; first += chunkSize) {
    const std::size_t count = std::min(chunkSize, n - first);
    // Each chunk gets its own Results, as the engine produces them.
    Results part;
    const Results& all = batch.results;
    part.status.assign(all.status.begin() + first, all.status.begin() + first + count);
    part.patch.assign(all.patch.begin() + first, all.patch.begin() + first + count);
    part.cell.assign(all.cell.begin() + first, all.cell.begin() + first + count);
    part.params.assign(all.params.begin() + 3 * first, all.params.begin() + 3 * (first + count));
    part.closest.assign(all.closest.begin() + 3 * first, all.closest.begin() + 3 * (first + count));
    part.distance.assign(all.distance.begin() + first, all.distance.begin() + first + count);
    writer->WriteChunk(batch.points.data() + first * static_cast<std::size_t>(dim), count, part,
                       static_cast<std::int64_t>(first));
  }
  EXPECT_EQ(writer->rows(), static_cast<std::int64_t>(n));
  writer->Finish();
}

std::string G17(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.17g", value);
  return text;
}

// ---------------------------------------------------------------------------
// CSV

TEST(CsvResults, ExactBytes3D) {
  ScratchDir dir;
  const std::string path = dir.Path("r.csv");
  WriteBatch(path, 3, MakeBatch(3));
  EXPECT_EQ(ReadAll(path),
            "index,status,patch,cell,u,v,w,x,y,z,distance\n"
            "0,found,1,42,0.5,0.25,,1,2,3,0.125\n"
            "1,found,0,7,0.10000000000000001,0.33333333333333331,2.0000000000000001e-300,-0.5,1e+20,"
            "0.20000000000000001,0.30000000000000004\n"
            "2,none,-1,-1,,,,,,,\n"
            "3,invalid,-1,-1,,,,,,,\n");
}

TEST(CsvResults, TwoDimensionalLeavesZEmpty) {
  ScratchDir dir;
  const std::string path = dir.Path("r.CSV");
  WriteBatch(path, 2, MakeBatch(2), 1);
  EXPECT_EQ(ReadAll(path),
            "index,status,patch,cell,u,v,w,x,y,z,distance\n"
            "0,found,1,42,0.5,0.25,,1,2,,0.125\n"
            "1,found,0,7,0.10000000000000001,0.33333333333333331,2.0000000000000001e-300,-0.5,1e+20,,"
            "0.30000000000000004\n"
            "2,none,-1,-1,,,,,,,\n"
            "3,invalid,-1,-1,,,,,,,\n");
}

TEST(CsvResults, NumbersMatchPrintf17g) {
  // The writer formats with to_chars; the contract is printf's %.17g.
  ScratchDir dir;
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-320, 307);
  Batch batch;
  const std::size_t n = 20000;
  Results& r = batch.results;
  r.status.assign(n, Status::Found);
  r.patch.assign(n, 0);
  r.cell.assign(n, 0);
  for (std::size_t i = 0; i < 3 * n; ++i) r.params.push_back(unit(rng) * std::pow(10.0, exponent(rng)));
  for (std::size_t i = 0; i < 3 * n; ++i) {
    r.closest.push_back(i % 7 == 0 ? std::round(unit(rng) * 1e6) : unit(rng) * std::pow(2.0, exponent(rng) / 3));
  }
  for (std::size_t i = 0; i < n; ++i) r.distance.push_back(std::fabs(unit(rng)) * 1e-3);
  r.params[0] = 5e-324;  // smallest subnormal
  r.params[1] = std::numeric_limits<double>::max();
  r.params[2] = -0.0;
  const std::string path = dir.Path("r.csv");
  WriteBatch(path, 3, batch, 4096);
  const std::string text = ReadAll(path);
  std::size_t pos = text.find('\n') + 1;
  for (std::size_t i = 0; i < n; ++i) {
    std::string expected = std::to_string(i) + ",found,0,0";
    for (int k = 0; k < 3; ++k) expected += "," + G17(r.params[3 * i + k]);
    for (int k = 0; k < 3; ++k) expected += "," + G17(r.closest[3 * i + k]);
    expected += "," + G17(r.distance[i]) + "\n";
    ASSERT_EQ(text.compare(pos, expected.size(), expected), 0) << "row " << i << ": " << expected;
    pos += expected.size();
  }
  EXPECT_EQ(pos, text.size());
}

// ---------------------------------------------------------------------------
// PLY

const char* const kPlyHeaderBody =
    "element vertex 4\ncomment            \n"
    "property double x\nproperty double y\nproperty double z\nproperty uchar status\nproperty int patch\n"
    "property int cell\nproperty double u\nproperty double v\nproperty double w\nproperty double cx\n"
    "property double cy\nproperty double cz\nproperty double distance\n";

TEST(PlyResults, HeaderAndValuesReadBack) {
  ScratchDir dir;
  for (int dim : {2, 3}) {
    SCOPED_TRACE(dim);
    const std::string path = dir.Path("r.ply");
    const Batch batch = MakeBatch(dim);
    WriteBatch(path, dim, batch, 3);
    const std::string text = ReadAll(path);
    EXPECT_EQ(
        text.substr(0, text.find("end_header\n") + 11),
        std::string("ply\nformat binary_little_endian 1.0\ncomment invmap invert results (docs/formats.md section 5)\n") +
            kPlyHeaderBody + "end_header\n");
    PlyReader reader(path);
    EXPECT_EQ(reader.header().elements[0].properties[3].type, PlyType::UInt8);
    EXPECT_EQ(reader.header().elements[0].properties[5].type, PlyType::Int32);
    PlyRecord record;
    const Results& r = batch.results;
    for (std::size_t i = 0; i < 4; ++i) {
      ASSERT_TRUE(reader.ReadRecord(&record));
      const auto same = [](double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); };
      for (int k = 0; k < 3; ++k) {
        EXPECT_TRUE(same(record.Scalar(k), k < dim ? batch.points[i * dim + k] : 0.0)) << i << " " << k;
      }
      EXPECT_EQ(record.Scalar(3), static_cast<double>(r.status[i]));
      const bool found = r.status[i] == Status::Found;
      EXPECT_EQ(record.Scalar(4), found ? r.patch[i] : -1);
      EXPECT_EQ(record.Scalar(5), found ? r.cell[i] : -1);
      for (int k = 0; k < 3; ++k) EXPECT_TRUE(same(record.Scalar(6 + k), found ? r.params[3 * i + k] : kNan));
      for (int k = 0; k < 3; ++k) {
        EXPECT_TRUE(same(record.Scalar(9 + k), found ? (k < dim ? r.closest[3 * i + k] : 0.0) : kNan));
      }
      EXPECT_TRUE(same(record.Scalar(12), r.distance[i]));
    }
    EXPECT_FALSE(reader.ReadRecord(&record));
    EXPECT_EQ(text.size(), static_cast<std::size_t>(reader.header().dataOffset) + 4 * 89);
  }
}

/// The red, green, blue of the rows of a coloured result file.
std::vector<std::array<int, 3>> Colors(const std::string& path) {
  PlyReader reader(path);
  const PlyElement& vertex = reader.header().elements[0];
  const int red = vertex.FindProperty("red");
  EXPECT_EQ(red, 13);
  EXPECT_EQ(vertex.FindProperty("blue"), 15);
  std::vector<std::array<int, 3>> colors;
  PlyRecord record;
  while (reader.ReadRecord(&record)) {
    colors.push_back({static_cast<int>(record.Scalar(13)), static_cast<int>(record.Scalar(14)),
                      static_cast<int>(record.Scalar(15))});
  }
  return colors;
}

std::array<int, 3> Viridis(double t) {
  unsigned char rgb[3];
  ViridisColor(t, rgb);
  return {rgb[0], rgb[1], rgb[2]};
}

TEST(PlyResults, ColorsWithAGivenRange) {
  ScratchDir dir;
  const std::string path = dir.Path("r.ply");
  ResultWriteOptions options;
  options.colorByDistance = true;
  options.colorMin = 0.0;
  options.colorMax = 0.25;
  WriteBatch(path, 3, MakeBatch(3), 4, options);
  const auto colors = Colors(path);
  ASSERT_EQ(colors.size(), 4u);
  EXPECT_EQ(colors[0], Viridis(0.5));
  EXPECT_EQ(colors[1], Viridis(1.0));  // clamped: 0.3 > 0.25
  EXPECT_EQ(colors[2], (std::array<int, 3>{128, 128, 128}));
  EXPECT_EQ(colors[3], (std::array<int, 3>{128, 128, 128}));
  EXPECT_NE(ReadAll(path).find("comment red green blue: viridis colormap of distance from 0 to 0.25"),
            std::string::npos);
}

TEST(PlyResults, ColorsOverTheFoundRangeInASecondPass) {
  ScratchDir dir;
  const std::string path = dir.Path("r.ply");
  ResultWriteOptions options;
  options.colorByDistance = true;
  WriteBatch(path, 3, MakeBatch(3), 1, options);
  const auto colors = Colors(path);
  EXPECT_EQ(colors[0], Viridis(0.0));
  EXPECT_EQ(colors[1], Viridis(1.0));
  EXPECT_EQ(colors[2], (std::array<int, 3>{128, 128, 128}));
  const std::string text = ReadAll(path);
  EXPECT_NE(text.find("comment red green blue: viridis colormap of distance from 0.125 to 0.30000000000000004 "),
            std::string::npos);
  EXPECT_EQ(text.size(), text.find("end_header\n") + 11 + 4 * 92);
}

TEST(PlyResults, ViridisEnds) {
  EXPECT_EQ(Viridis(0.0), (std::array<int, 3>{68, 1, 84}));     // #440154
  EXPECT_EQ(Viridis(0.5), (std::array<int, 3>{33, 145, 140}));  // #21918c
  EXPECT_EQ(Viridis(1.0), (std::array<int, 3>{253, 231, 37}));  // #fde725
  EXPECT_EQ(Viridis(-3.0), Viridis(0.0));
  EXPECT_EQ(Viridis(kNan), (std::array<int, 3>{128, 128, 128}));
}

// ---------------------------------------------------------------------------
// npy

TEST(NpyResults, HeaderAndValues) {
  ScratchDir dir;
  for (int dim : {2, 3}) {
    SCOPED_TRACE(dim);
    const std::string path = dir.Path("r.npy");
    const Batch batch = MakeBatch(dim);
    WriteBatch(path, dim, batch, 3);
    const std::string bytes = ReadAll(path);
    ASSERT_EQ(bytes.size(), 128u + 4 * 11 * 8);
    std::string dict = "{'descr': '<f8', 'fortran_order': False, 'shape': (4, 11), }";
    dict.resize(117, ' ');
    EXPECT_EQ(bytes.substr(0, 128), std::string("\x93NUMPY\x01\x00\x76\x00", 10) + dict + "\n");

    InputBuffer input(path);
    const NpyHeader header = ReadNpyHeader(input);
    EXPECT_EQ(header.shape, (std::vector<std::int64_t>{4, 11}));
    EXPECT_EQ(header.dataOffset, 128);
    const Results& r = batch.results;
    for (std::size_t i = 0; i < 4; ++i) {
      double row[11];
      for (int c = 0; c < 11; ++c) row[c] = LoadValue<double>(bytes.data() + 128 + (i * 11 + c) * 8, false);
      const bool found = r.status[i] == Status::Found;
      const double expected[11] = {static_cast<double>(i),
                                   static_cast<double>(r.status[i]),
                                   found ? r.patch[i] : -1.0,
                                   found ? static_cast<double>(r.cell[i]) : -1.0,
                                   found ? r.params[3 * i] : kNan,
                                   found ? r.params[3 * i + 1] : kNan,
                                   found ? r.params[3 * i + 2] : kNan,
                                   found ? r.closest[3 * i] : kNan,
                                   found ? r.closest[3 * i + 1] : kNan,
                                   found && dim == 3 ? r.closest[3 * i + 2] : kNan,
                                   found ? r.distance[i] : kNan};
      for (int c = 0; c < 11; ++c) {
        EXPECT_TRUE(row[c] == expected[c] || (std::isnan(row[c]) && std::isnan(expected[c]))) << i << " " << c;
      }
    }
  }
}

// ---------------------------------------------------------------------------
// Signed distances (CAD solids): a last column in every format

TEST(SignedResults, LastColumnAndColoursCentredOnZero) {
  // CAD solids' signed distances: the extra column signed_distance, last in
  // every format, and the colours it drives.
  ScratchDir dir;
  const Batch batch = MakeBatch(3);
  const double signedDistances[4] = {-0.125, 0.30000000000000004, kNan, kNan};
  ResultWriteOptions options;
  options.extraColumns = {"signed_distance"};
  options.signedColorColumn = 0;
  auto write = [&](const std::string& path, const ResultWriteOptions& o) {
    const auto writer = OpenResultWriter(path, 3, o);
    writer->WriteChunk(batch.points.data(), 4, batch.results, 0, signedDistances);
    writer->Finish();
  };
  const std::string csv = dir.Path("s.csv");
  write(csv, options);
  EXPECT_EQ(ReadAll(csv),
            "index,status,patch,cell,u,v,w,x,y,z,distance,signed_distance\n"
            "0,found,1,42,0.5,0.25,,1,2,3,0.125,-0.125\n"
            "1,found,0,7,0.10000000000000001,0.33333333333333331,2.0000000000000001e-300,-0.5,1e+20,"
            "0.20000000000000001,0.30000000000000004,0.30000000000000004\n"
            "2,none,-1,-1,,,,,,,,\n"
            "3,invalid,-1,-1,,,,,,,,\n");

  // PLY: the colours centred on 0 (white) over [-m, m], m the largest
  // |signed distance| found; the property last.
  const std::string ply = dir.Path("s.ply");
  ResultWriteOptions colored = options;
  colored.colorByDistance = true;
  write(ply, colored);
  const std::string text = ReadAll(ply);
  EXPECT_NE(text.find("property uchar blue\nproperty double signed_distance\nend_header"), std::string::npos);
  EXPECT_NE(text.find("cool-warm colormap of signed_distance from -0.30000000000000004 to 0.30000000000000004"),
            std::string::npos);
  const std::size_t data = text.find("end_header\n") + 11;
  const std::size_t record = 3 * 8 + 1 + 2 * 4 + 7 * 8 + 3 + 8;
  ASSERT_EQ(text.size(), data + 4 * record);
  unsigned char first[3], second[3];
  DivergingColor((-0.125 + 0.30000000000000004) / 0.6000000000000001, first);
  DivergingColor(1.0, second);
  const std::size_t colors = 3 * 8 + 1 + 2 * 4 + 7 * 8;
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(static_cast<unsigned char>(text[data + colors + k]), first[k]);
    EXPECT_EQ(static_cast<unsigned char>(text[data + record + colors + k]), second[k]);
  }
}

TEST(SignedResults, DivergingMapEndsAndMiddle) {
  unsigned char rgb[3];
  DivergingColor(0.0, rgb);
  EXPECT_EQ((std::array<int, 3>{rgb[0], rgb[1], rgb[2]}), (std::array<int, 3>{59, 76, 192}));
  DivergingColor(0.5, rgb);
  EXPECT_EQ((std::array<int, 3>{rgb[0], rgb[1], rgb[2]}), (std::array<int, 3>{221, 221, 221}));
  DivergingColor(1.0, rgb);
  EXPECT_EQ((std::array<int, 3>{rgb[0], rgb[1], rgb[2]}), (std::array<int, 3>{180, 4, 38}));
  DivergingColor(kNan, rgb);
  EXPECT_EQ((std::array<int, 3>{rgb[0], rgb[1], rgb[2]}), (std::array<int, 3>{128, 128, 128}));
}

// ---------------------------------------------------------------------------
// Streaming and the complete-or-absent rule

TEST(ResultWriter, ChunkingDoesNotChangeTheBytes) {
  ScratchDir dir;
  ResultWriteOptions colored;
  colored.colorByDistance = true;
  for (const char* name : {"r.csv", "r.ply", "r.npy"}) {
    SCOPED_TRACE(name);
    WriteBatch(dir.Path(name), 3, MakeBatch(3), 4, colored);
    const std::string whole = ReadAll(dir.Path(name));
    for (std::size_t chunk : {1u, 3u}) {
      WriteBatch(dir.Path(name), 3, MakeBatch(3), chunk, colored);
      EXPECT_EQ(ReadAll(dir.Path(name)), whole);
    }
  }
}

TEST(ResultWriter, OutputAppearsOnlyOnFinish) {
  ScratchDir dir;
  const Batch batch = MakeBatch(3);
  for (const char* name : {"r.csv", "r.ply", "r.npy"}) {
    SCOPED_TRACE(name);
    const std::string path = dir.Path(name);
    {
      const auto writer = OpenResultWriter(path, 3);
      writer->WriteChunk(batch.points.data(), 4, batch.results, 0);
      EXPECT_FALSE(std::filesystem::exists(path));
    }
    // Never finished: no output and no temporary file left.
    EXPECT_FALSE(std::filesystem::exists(path));
    EXPECT_EQ(dir.EntryCount(), 0u);

    // An old output stays until the new one is complete, then is replaced.
    dir.Write(name, "old");
    {
      const auto writer = OpenResultWriter(path, 3);
      writer->WriteChunk(batch.points.data(), 4, batch.results, 0);
      EXPECT_EQ(ReadAll(path), "old");
      // A failure mid-way (rows out of order) leaves the old file too.
      EXPECT_THROW(writer->WriteChunk(batch.points.data(), 4, batch.results, 0), std::invalid_argument);
    }
    EXPECT_EQ(ReadAll(path), "old");
    WriteBatch(path, 3, batch);
    EXPECT_NE(ReadAll(path), "old");
    EXPECT_EQ(dir.EntryCount(), 1u);
    std::filesystem::remove(path);
  }
}

TEST(ResultWriter, MisuseThrows) {
  ScratchDir dir;
  const Batch batch = MakeBatch(3);
  const auto writer = OpenResultWriter(dir.Path("r.ply"), 3);
  EXPECT_THROW(writer->WriteChunk(batch.points.data(), 4, batch.results, 1), std::invalid_argument);
  EXPECT_THROW(writer->WriteChunk(batch.points.data(), 5, batch.results, 0), std::invalid_argument);
  EXPECT_THROW(writer->WriteChunk(nullptr, 4, batch.results, 0), std::invalid_argument);
  writer->Finish();
  EXPECT_THROW(writer->Finish(), std::logic_error);
  EXPECT_THROW(writer->WriteChunk(batch.points.data(), 4, batch.results, 0), std::logic_error);
  EXPECT_THROW(OpenResultWriter(dir.Path("r.csv"), 4), std::invalid_argument);
}

TEST(ResultWriter, UnwritableOutputsAreOutputErrors) {
  ScratchDir dir;
  const auto expectOutputError = [&](const std::string& path, const std::string& part) {
    ExpectInputError([&] { OpenResultWriter(path, 3); }, path, 0, part, InputError::Kind::Output);
  };
  expectOutputError(dir.Path("missing/r.csv"), "cannot create a file in");
  expectOutputError(dir.path().string() + "/", "unknown result file extension");
  std::filesystem::create_directory(dir.Path("d.csv"));
  expectOutputError(dir.Path("d.csv"), "is a directory");
  dir.Write("file", "x");
  expectOutputError(dir.Path("file/r.npy"), "cannot create a file in");
  expectOutputError(dir.Path("r.txt"), "unknown result file extension '.txt'");
}

/// Child process body of FullDiskIsAnOutputError: writes rows to `path`
/// under a 64 KiB file size limit and exits with 0 when the writer reports
/// an Output error and leaves no file.
void WriteUnderAFileSizeLimit(const std::string& path) {
  std::signal(SIGXFSZ, SIG_IGN);
  rlimit limit{};
  limit.rlim_cur = limit.rlim_max = 1 << 16;
  setrlimit(RLIMIT_FSIZE, &limit);
  try {
    const Batch batch = MakeBatch(3);
    const auto writer = OpenResultWriter(path, 3);
    for (std::int64_t first = 0; first < 400000; first += 4) {
      writer->WriteChunk(batch.points.data(), 4, batch.results, first);
    }
    writer->Finish();
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    std::exit(e.kind() == InputError::Kind::Output && !std::filesystem::exists(path) ? 0 : 1);
  }
  std::exit(2);
}

TEST(ResultWriter, FullDiskIsAnOutputError) {
  // A file size limit makes write() fail with EFBIG as a full disk fails
  // with ENOSPC; it runs in a child process so the limit stays there.
  ScratchDir dir;
  const std::string path = dir.Path("big.csv");
  EXPECT_EXIT(WriteUnderAFileSizeLimit(path), ::testing::ExitedWithCode(0), "big.csv: cannot write: File too large");
  EXPECT_EQ(dir.EntryCount(), 0u);
}

}  // namespace
}  // namespace invmap::io
