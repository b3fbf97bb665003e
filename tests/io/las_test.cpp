// The LAS point reader and trim's LAS output against an independent writer
// built from the specification's tables (tests/support/las_writer): every
// version 1.0 to 1.4 with every point data record format it defines, extra
// bytes, VLRs, EVLRs and waveform data, and bad files refused with the
// file named before anything is allocated from their headers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "io/input_error.h"
#include "io/point_reader.h"
#include "io/trim_writer.h"
#include "tests/io/io_scratch.h"
#include "tests/support/las_writer.h"

namespace invmap::io {
namespace {

using scratch::ExpectInputError;
using scratch::ReadAll;
using scratch::ScratchDir;
using testing::LasFile;
using testing::LasPoint;
using testing::LasRecord;

/// Everything a reader gives, chunk after chunk.
struct ReadBack {
  std::vector<double> xyz;
  std::vector<std::string> records;
  std::int64_t countHint = -1;
  int dim = 0;
};

ReadBack ReadEverything(const std::string& path, std::size_t chunkPoints, int forcedDim = 0) {
  PointReadOptions options;
  options.forcedDim = forcedDim;
  auto reader = OpenPointReader(path, options);
  ReadBack back;
  back.countHint = reader->totalCountHint();
  back.dim = reader->dim();
  PointChunk chunk;
  while (reader->ReadChunk(chunkPoints, &chunk)) {
    back.xyz.insert(back.xyz.end(), chunk.xyz.begin(), chunk.xyz.end());
    for (std::size_t i = 0; i < chunk.count; ++i) {
      back.records.push_back(chunk.raw.substr(chunk.rawOffsets[i], chunk.rawOffsets[i + 1] - chunk.rawOffsets[i]));
    }
  }
  return back;
}

/// Empty when a == b, else where they first differ (binary files print
/// badly in full).
std::string Difference(const std::string& a, const std::string& b) {
  if (a == b) return "";
  std::size_t i = 0;
  while (i < a.size() && i < b.size() && a[i] == b[i]) ++i;
  return "sizes " + std::to_string(a.size()) + " and " + std::to_string(b.size()) + ", first difference at byte " +
         std::to_string(i);
}

/// Trims `input` to the points with keep[i] != 0 through TrimWriter.
void Trim(const std::string& input, const std::string& output, const std::vector<unsigned char>& keep,
          std::size_t chunkPoints) {
  auto reader = OpenPointReader(input, PointReadOptions{});
  TrimWriter writer(output, reader->layout());
  PointChunk chunk;
  while (reader->ReadChunk(chunkPoints, &chunk)) {
    writer.WriteChunk(chunk, keep.data() + chunk.firstIndex);
  }
  writer.Finish();
}

/// A file of LAS 1.`minor` and `format` with everything the version allows:
/// random points, extra bytes, VLRs, (1.0) the start signature, (1.3, 1.4
/// wave formats) waveform data, (1.4) EVLRs.
LasFile SampleFile(int minor, int format, std::size_t count, std::mt19937_64* rng) {
  LasFile file;
  file.versionMinor = minor;
  file.pointFormat = format;
  file.extraBytes = (minor + format) % 3 == 0 ? 0 : static_cast<std::size_t>(1 + format % 4);
  file.describeExtraBytes = minor == 4 && file.extraBytes > 0;
  file.scale[0] = 0.001;
  file.scale[1] = 0.25;
  file.scale[2] = 1e-7;
  file.offset[0] = 512000.5;
  file.offset[1] = -4100000.0;
  file.offset[2] = 12.75;
  file.points = testing::RandomLasPoints(count, format, file.extraBytes, 2000000000, rng);
  file.vlrs.push_back({"LASF_Projection", 34735, "GeoKeyDirectoryTag", std::string("\x01\x00\x01\x00\x00\x00\x00\x00", 8)});
  file.vlrs.push_back({"invmap_test", 7, "an empty record", ""});
  const bool wave = format == 4 || format == 5 || format == 9 || format == 10;
  if (wave) {
    // The Waveform Packet Descriptor (record 100 + index) the formats require.
    file.vlrs.push_back({"LASF_Spec", 101, "waveform packet descriptor", std::string(26, '\x03')});
    if (minor >= 3) file.waveformPackets = std::string(60 * 1001, '\x42');
  }
  if (minor == 4) {
    file.evlrs.push_back({"LASF_Projection", 2112, "OGC WKT", "GEOGCS[\"WGS 84\"]"});
    file.evlrs.push_back({"invmap_test", 9, "a large payload", std::string(70000, '\x17')});
  }
  return file;
}

TEST(LasTest, EveryVersionAndFormatReadsAsTheSpecificationLaysItOut) {
  ScratchDir dir;
  std::mt19937_64 rng(29);
  for (int minor = 0; minor <= 4; ++minor) {
    for (int format = 0; format <= testing::LasMaxFormat(minor); ++format) {
      SCOPED_TRACE("LAS 1." + std::to_string(minor) + " format " + std::to_string(format));
      const LasFile file = SampleFile(minor, format, 257, &rng);
      const std::string path = dir.Write("in.las", testing::WriteLas(file));
      const ReadBack back = ReadEverything(path, 37);
      EXPECT_EQ(back.dim, 3);
      EXPECT_EQ(back.countHint, 257);
      ASSERT_EQ(back.records, testing::LasRecords(file));
      ASSERT_EQ(back.xyz.size(), 3 * file.points.size());
      for (std::size_t i = 0; i < file.points.size(); ++i) {
        const std::int32_t values[3] = {file.points[i].x, file.points[i].y, file.points[i].z};
        for (int k = 0; k < 3; ++k) {
          ASSERT_EQ(back.xyz[3 * i + k], values[k] * file.scale[k] + file.offset[k]) << "point " << i << " axis " << k;
        }
      }
      // A 2D geometry takes x and y.
      const ReadBack flat = ReadEverything(path, 1000, 2);
      ASSERT_EQ(flat.xyz.size(), 2 * file.points.size());
      EXPECT_EQ(flat.xyz[2], back.xyz[3]);
      EXPECT_EQ(flat.xyz[3], back.xyz[4]);
    }
  }
}

TEST(LasTest, TrimWritesWhatTheSpecificationsWriterWritesForTheKeptPoints) {
  ScratchDir dir;
  std::mt19937_64 rng(7);
  for (int minor = 0; minor <= 4; ++minor) {
    for (int format = 0; format <= testing::LasMaxFormat(minor); ++format) {
      for (const bool legacy : {true, false}) {
        if (!legacy && minor < 4) continue;
        SCOPED_TRACE("LAS 1." + std::to_string(minor) + " format " + std::to_string(format) +
                     (legacy ? "" : " without legacy counts"));
        LasFile file = SampleFile(minor, format, 300, &rng);
        file.legacyCounts = legacy;
        const std::string input = dir.Write("in.las", testing::WriteLas(file));
        std::vector<unsigned char> keep(file.points.size());
        LasFile kept = file;
        kept.points.clear();
        for (std::size_t i = 0; i < keep.size(); ++i) {
          keep[i] = std::uniform_int_distribution<int>(0, 2)(rng) == 0;
          if (keep[i]) kept.points.push_back(file.points[i]);
        }
        Trim(input, dir.Path("out.las"), keep, 64);
        // Byte for byte: the kept records, the header's counts by return
        // (legacy and 1.4), bounds, the offsets of the EVLRs and waveform
        // data, every VLR and EVLR.
        ASSERT_EQ(Difference(ReadAll(dir.Path("out.las")), testing::WriteLas(kept)), "");
        // And it reads back as the kept points.
        EXPECT_EQ(ReadEverything(dir.Path("out.las"), 1000).records, testing::LasRecords(kept));
      }
    }
  }
}

TEST(LasTest, TrimKeepingAllOrNothing) {
  ScratchDir dir;
  std::mt19937_64 rng(3);
  LasFile file = SampleFile(4, 7, 100, &rng);
  const std::string input = dir.Write("in.las", testing::WriteLas(file));
  Trim(input, dir.Path("all.las"), std::vector<unsigned char>(100, 1), 30);
  EXPECT_EQ(Difference(ReadAll(dir.Path("all.las")), ReadAll(input)), "");
  Trim(input, dir.Path("none.las"), std::vector<unsigned char>(100, 0), 30);
  LasFile empty = file;
  empty.points.clear();
  // No point: counts zero, bounds zero, the EVLRs right after the VLRs.
  EXPECT_EQ(Difference(ReadAll(dir.Path("none.las")), testing::WriteLas(empty)), "");
  EXPECT_TRUE(ReadEverything(dir.Path("none.las"), 10).records.empty());
}

TEST(LasTest, HeaderPaddingAndBytesBeforeThePointsPassThrough) {
  ScratchDir dir;
  std::mt19937_64 rng(5);
  for (const int minor : {0, 2, 3}) {
    LasFile file = SampleFile(minor, 1, 50, &rng);
    file.headerPadding = 13;  // user data in the header, allowed before 1.4
    file.bytesBeforePoints = "user bytes";
    const std::string input = dir.Write("in.las", testing::WriteLas(file));
    EXPECT_EQ(ReadEverything(input, 7).records, testing::LasRecords(file));
    std::vector<unsigned char> keep(50, 0);
    keep[3] = keep[49] = 1;
    LasFile kept = file;
    kept.points = {file.points[3], file.points[49]};
    Trim(input, dir.Path("out.las"), keep, 7);
    EXPECT_EQ(Difference(ReadAll(dir.Path("out.las")), testing::WriteLas(kept)), "") << "LAS 1." << minor;
  }
}

TEST(LasTest, NegativeScaleGivesBoundsInTheRightOrder) {
  ScratchDir dir;
  std::mt19937_64 rng(11);
  LasFile file = SampleFile(2, 0, 40, &rng);
  file.scale[1] = -0.5;
  const std::string input = dir.Write("in.las", testing::WriteLas(file));
  std::vector<unsigned char> keep(40, 1);
  keep[0] = 0;
  LasFile kept = file;
  kept.points.erase(kept.points.begin());
  Trim(input, dir.Path("out.las"), keep, 8);
  EXPECT_EQ(Difference(ReadAll(dir.Path("out.las")), testing::WriteLas(kept)), "");
}

/// Overwrites `size` bytes of `bytes` at `offset` with `value`.
template <class T>
void Poke(std::string* bytes, std::size_t offset, T value) {
  std::memcpy(bytes->data() + offset, &value, sizeof(T));
}

TEST(LasTest, BadFilesAreRefusedNamingTheFile) {
  ScratchDir dir;
  std::mt19937_64 rng(13);
  const auto withoutExtraBytes = [&](int minor, int format) {
    LasFile file = SampleFile(minor, format, 20, &rng);
    file.extraBytes = 0;
    file.describeExtraBytes = false;
    return testing::WriteLas(file);
  };
  const std::string good12 = withoutExtraBytes(2, 3);
  const std::string good14 = withoutExtraBytes(4, 6);
  const auto expectRefused = [&](const std::string& bytes, const std::string& part, const std::string& name = "bad.las") {
    const std::string path = dir.Write(name, bytes);
    SCOPED_TRACE(part);
    ExpectInputError([&] { ReadEverything(path, 100); }, path, 0, part);
  };
  expectRefused("PLY\nnot a LAS file at all, but long enough to hold a header" + std::string(300, ' '),
                "does not start with 'LASF'");
  expectRefused(good12.substr(0, 100), "ends inside the LAS header");
  std::string bytes = good12;
  Poke<std::uint8_t>(&bytes, 24, 2);
  expectRefused(bytes, "LAS version 2.2 is not supported");
  bytes = good12;
  Poke<std::uint8_t>(&bytes, 25, 5);
  expectRefused(bytes, "LAS version 1.5 is not supported");
  bytes = good12;
  Poke<std::uint8_t>(&bytes, 104, 11);
  expectRefused(bytes, "unknown point data record format 11");
  bytes = good12;
  Poke<std::uint8_t>(&bytes, 104, 0x83);  // how LASzip marks format 3 compressed
  expectRefused(bytes, "compressed LAZ is not supported");
  bytes = good12;
  Poke<std::uint16_t>(&bytes, 105, 33);
  expectRefused(bytes, "point data record length 33 is shorter than format 3's 34 bytes");
  bytes = good12;
  Poke<double>(&bytes, 139, 0.0);
  expectRefused(bytes, "y scale factor is 0");
  bytes = good12;
  Poke<double>(&bytes, 171, std::nan(""));
  expectRefused(bytes, "z offset is nan");
  // Lying counts: more points than the file holds, refused before any
  // allocation (a 1.4 count of 2^60 too).
  bytes = good12;
  Poke<std::uint32_t>(&bytes, 107, 21);
  expectRefused(bytes, "the header's 21 point records of 34 bytes");
  bytes = good14;
  Poke<std::uint64_t>(&bytes, 247, std::uint64_t{1} << 60);
  Poke<std::uint32_t>(&bytes, 107, 0);
  expectRefused(bytes, "point records of 30 bytes");
  bytes = testing::WriteLas(SampleFile(4, 1, 20, &rng));
  Poke<std::uint32_t>(&bytes, 107, 19);
  expectRefused(bytes, "the legacy point count (19) disagrees with the point count (20)");
  // Wrong offsets.
  bytes = good12;
  Poke<std::uint32_t>(&bytes, 96, 100);
  expectRefused(bytes, "offset to point data (100) lies inside the 227-byte header");
  bytes = good12;
  Poke<std::uint32_t>(&bytes, 96, 0xFFFFFFF0u);
  expectRefused(bytes, "do not fit in the file");
  bytes = good12;
  Poke<std::uint32_t>(&bytes, 100, 0xFFFFFFFFu);  // 4 billion VLRs: refused at the first that does not fit
  expectRefused(bytes, "variable length record 3 of 4294967295");
  bytes = good12;
  Poke<std::uint16_t>(&bytes, 227 + 20, 60000);
  expectRefused(bytes, "variable length record 1 of 2 (user 'LASF_Projection', record 34735) ends at byte");
  bytes = good14;
  Poke<std::uint64_t>(&bytes, 235, 400);
  expectRefused(bytes, "the first extended variable length record (byte 400) is not after the point records");
  bytes = good14;
  Poke<std::uint32_t>(&bytes, 243, 3);
  expectRefused(bytes, "extended variable length record 3 of 3 at byte");
  bytes = good14;
  bytes.resize(bytes.size() - 5);
  expectRefused(bytes, "extended variable length record 2 of 2 (user 'invmap_test', record 9) of 70000 bytes");
  bytes = testing::WriteLas(SampleFile(3, 4, 20, &rng));
  Poke<std::uint64_t>(&bytes, 227, 500);
  expectRefused(bytes, "the waveform data packet record's start (byte 500) is not between");
  // A file cut short: its header claims records it no longer holds.
  expectRefused(good12.substr(0, good12.size() - 10), "do not fit in the file's");
  // LASzip's VLR in an uncompressed-looking header.
  LasFile zipped = SampleFile(2, 1, 5, &rng);
  zipped.vlrs.push_back({"laszip encoded", 22204, "", std::string(34, '\0')});
  expectRefused(testing::WriteLas(zipped), "compressed LAZ is not supported");
  // And the .laz extension, whatever the content.
  expectRefused(good12, "compressed LAZ is not supported", "scan.laz");
}

}  // namespace
}  // namespace invmap::io
