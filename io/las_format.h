// The ASPRS LAS point cloud format, versions 1.0 to 1.4 (the 1.4 R15
// specification's tables): where the public header block keeps its fields,
// the sizes of the point data record formats 0 to 10, and the reading and
// checking of a header so that nothing it claims is trusted before the file
// is known to hold it. The point reader streams the records after it; trim
// copies them and rewrites the counts and bounds (docs/point-clouds.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "io/file_io.h"

namespace invmap::io {

/// Byte offsets and sizes of the LAS public header block. Versions 1.0 to
/// 1.2 end after the bounds (227 bytes), 1.3 adds the waveform start (235),
/// 1.4 the extended records and 64-bit counts (375). All values are
/// little-endian.
namespace las {
inline constexpr std::size_t kVersionMajor = 24;    ///< unsigned char
inline constexpr std::size_t kVersionMinor = 25;    ///< unsigned char
inline constexpr std::size_t kHeaderSize = 94;      ///< unsigned short
inline constexpr std::size_t kPointDataOffset = 96; ///< unsigned long
inline constexpr std::size_t kVlrCount = 100;       ///< unsigned long
inline constexpr std::size_t kPointFormat = 104;    ///< unsigned char
inline constexpr std::size_t kRecordLength = 105;   ///< unsigned short
inline constexpr std::size_t kLegacyPointCount = 107;  ///< unsigned long
inline constexpr std::size_t kLegacyByReturn = 111;    ///< unsigned long[5]
inline constexpr std::size_t kScale = 131;    ///< double[3]: x, y, z
inline constexpr std::size_t kOffset = 155;   ///< double[3]: x, y, z
inline constexpr std::size_t kBounds = 179;   ///< double[6]: max x, min x, max y, min y, max z, min z
inline constexpr std::size_t kWaveformStart = 227;  ///< unsigned long long (1.3, 1.4)
inline constexpr std::size_t kEvlrStart = 235;      ///< unsigned long long (1.4)
inline constexpr std::size_t kEvlrCount = 243;      ///< unsigned long (1.4)
inline constexpr std::size_t kPointCount = 247;     ///< unsigned long long (1.4)
inline constexpr std::size_t kByReturn = 255;       ///< unsigned long long[15] (1.4)

inline constexpr int kLegacyReturns = 5;    ///< Entries of the legacy by-return counts.
inline constexpr int kExtendedReturns = 15; ///< Entries of the 1.4 by-return counts.

inline constexpr std::size_t kVlrHeaderBytes = 54;   ///< A variable length record's header.
inline constexpr std::size_t kEvlrHeaderBytes = 60;  ///< An extended variable length record's header.

/// Size of the public header block of LAS 1.`minor` (minor 0 to 4).
std::size_t StandardHeaderSize(int minor);

/// Bytes of point data record format `format` (0 to 10) without extra bytes.
std::size_t MinimumRecordLength(int format);

/// The return number of a point record of `format`: 3 bits in formats 0 to
/// 5, 4 bits in formats 6 to 10, in the low bits of byte 14.
inline int ReturnNumber(const char* record, int format) {
  const auto flags = static_cast<unsigned char>(record[14]);
  return format < 6 ? (flags & 0x07) : (flags & 0x0F);
}
}  // namespace las

/// What a LAS file's header says, checked against the file: what the point
/// reader needs to decode the records and what trim needs to write a LAS
/// file of the kept ones.
struct LasLayout {
  /// The input file: trim copies its header, variable length records and
  /// everything after the point records from it.
  std::string path;
  int versionMinor = 2;           ///< LAS 1.versionMinor.
  int pointFormat = 0;            ///< Point data record format, 0 to 10.
  std::size_t recordLength = 20;  ///< Bytes of a record, extra bytes included.
  double scale[3] = {1, 1, 1};    ///< Scale factors of X, Y, Z.
  double offset[3] = {0, 0, 0};   ///< Offsets of X, Y, Z.
  std::uint64_t pointDataOffset = 0;  ///< File offset of the first record.
  std::uint64_t pointCount = 0;       ///< Records in the file.
  std::uint64_t fileSize = 0;         ///< Bytes of the file.
  /// The header fills the legacy counts (always before 1.4; in a 1.4 file
  /// when its legacy point count is not zero): trim keeps them in step.
  bool legacyCounts = true;
  std::uint64_t waveformStart = 0;  ///< 1.3 and 1.4: the waveform data packet record's offset, 0 if none.
  std::uint64_t evlrStart = 0;      ///< 1.4: the first extended variable length record's offset.
  std::uint32_t evlrCount = 0;      ///< 1.4: extended variable length records.

  /// File offset just past the last point record.
  std::uint64_t pointDataEnd() const { return pointDataOffset + pointCount * recordLength; }
};

/// Reads and checks the header and variable length records of the LAS file
/// at the start of `input` (named `path`; a regular file, whose size is
/// known) and consumes everything up to the first point record. Throws
/// InputError naming the file for anything that is not a LAS 1.0 to 1.4
/// file with point data record format 0 to 10 (compressed LAZ data is
/// refused as such), for counts and offsets that the file cannot hold and
/// for a record length shorter than the format's.
LasLayout ReadLasHeader(InputBuffer& input, const std::string& path);

/// The message for a compressed LAZ file: what to do instead.
std::string LazRefusal();

}  // namespace invmap::io
