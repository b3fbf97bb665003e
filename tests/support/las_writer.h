// A LAS writer for the tests, written field by field from the tables of the
// ASPRS LAS specification (1.0 to 1.4 R15), independent of io/'s reader: it
// appends every header field, variable length record and point record
// attribute in the specification's order and computes the counts, bounds and
// offsets from the points it is given. The tests compare the reader with it
// and `trim`'s output with what it writes for the kept points.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace invmap::testing {

/// One point with every attribute of the LAS point data record formats (a
/// format writes the ones it has).
struct LasPoint {
  std::int32_t x = 0, y = 0, z = 0;  ///< Record values (coordinate = value * scale + offset).
  std::uint16_t intensity = 0;
  int returnNumber = 1;   ///< 3 bits in formats 0-5, 4 bits in 6-10.
  int returnCount = 1;    ///< Number of returns of the pulse, same widths.
  int classificationFlags = 0;  ///< Formats 6-10: 4 bits.
  int scannerChannel = 0;       ///< Formats 6-10: 2 bits.
  bool scanDirection = false;
  bool edgeOfFlightLine = false;
  std::uint8_t classification = 0;
  std::int16_t scanAngle = 0;  ///< Formats 0-5: the scan angle rank (-90 to 90); 6-10: the scan angle.
  std::uint8_t userData = 0;
  std::uint16_t pointSourceId = 0;
  double gpsTime = 0.0;
  std::uint16_t red = 0, green = 0, blue = 0, nir = 0;
  std::uint8_t wavePacketIndex = 0;
  std::uint64_t waveformOffset = 0;
  std::uint32_t waveformSize = 0;
  float waveformLocation = 0.0F, dx = 0.0F, dy = 0.0F, dz = 0.0F;
  std::string extraBytes;  ///< The record's extra bytes (LasFile::extraBytes of them).
};

/// A variable length record (or, in extendedRecords, an extended one).
struct LasRecord {
  std::string userId;  ///< Up to 16 characters.
  std::uint16_t recordId = 0;
  std::string description;  ///< Up to 32 characters.
  std::string payload;
};

/// Everything a test LAS file holds.
struct LasFile {
  int versionMinor = 2;  ///< LAS 1.versionMinor, 0 to 4.
  int pointFormat = 0;   ///< 0 to 10.
  std::size_t extraBytes = 0;    ///< Extra bytes after each record's standard fields.
  bool describeExtraBytes = false;  ///< Add an Extra Bytes VLR (1.4) describing them as uchar[extraBytes].
  double scale[3] = {0.01, 0.01, 0.01};
  double offset[3] = {0.0, 0.0, 0.0};
  std::vector<LasPoint> points;
  std::vector<LasRecord> vlrs;
  std::size_t headerPadding = 0;  ///< Bytes added to the header (allowed before 1.4).
  std::string bytesBeforePoints;  ///< After the VLRs (LAS 1.0 adds its start signature before these).
  std::vector<LasRecord> evlrs;   ///< LAS 1.4 only.
  /// LAS 1.3 and 1.4 with formats 4, 5, 9, 10: an internal waveform data
  /// packet record of this payload after the points (first of the EVLRs).
  std::string waveformPackets;
  bool legacyCounts = true;  ///< LAS 1.4: fill the legacy counts (formats 0-5 only).
};

/// The records as the specification lays them out, one string per point.
std::vector<std::string> LasRecords(const LasFile& file);

/// The whole file.
std::string WriteLas(const LasFile& file);

/// Bytes of format `format`'s standard fields, from the specification's tables.
std::size_t LasRecordLength(int format);

/// The highest point data record format of LAS 1.`minor`.
int LasMaxFormat(int minor);

/// `count` points with every attribute random (record values within
/// +-`extent`), return numbers within their format's range.
std::vector<LasPoint> RandomLasPoints(std::size_t count, int format, std::size_t extraBytes, std::int32_t extent,
                                      std::mt19937_64* random);

}  // namespace invmap::testing
