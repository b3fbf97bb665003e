#include "tests/support/las_writer.h"

#include <algorithm>
#include <cstring>
#include <limits>

namespace invmap::testing {
namespace {

/// Appends values little-endian (the specification: "All data are in
/// little-endian format").
class Bytes {
 public:
  template <class T>
  void Put(T value) {
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    const std::uint16_t one = 1;
    if (*reinterpret_cast<const unsigned char*>(&one) == 0) std::reverse(raw, raw + sizeof(T));
    text_.append(raw, sizeof(T));
  }
  /// A char[n] field: the text, then NULs.
  void PutText(const std::string& text, std::size_t n) {
    text_ += text.substr(0, n);
    text_.append(n - std::min(n, text.size()), '\0');
  }
  void PutRaw(const std::string& raw) { text_ += raw; }
  std::size_t size() const { return text_.size(); }
  std::string& text() { return text_; }

 private:
  std::string text_;
};

bool HasGpsTime(int format) { return format != 0 && format != 2; }
bool HasRgb(int format) { return format == 2 || format == 3 || format == 5 || format == 7 || format == 8 || format == 10; }
bool HasNir(int format) { return format == 8 || format == 10; }
bool HasWavePacket(int format) { return format == 4 || format == 5 || format == 9 || format == 10; }

/// One record, field by field as in the tables "Point Data Record Format N".
std::string Record(const LasPoint& p, int format, std::size_t extraBytes) {
  Bytes b;
  b.Put<std::int32_t>(p.x);
  b.Put<std::int32_t>(p.y);
  b.Put<std::int32_t>(p.z);
  b.Put<std::uint16_t>(p.intensity);
  if (format <= 5) {
    // Return number bits 0-2, number of returns 3-5, scan direction 6, edge 7.
    b.Put<std::uint8_t>(static_cast<std::uint8_t>((p.returnNumber & 7) | ((p.returnCount & 7) << 3) |
                                                  (p.scanDirection ? 0x40 : 0) | (p.edgeOfFlightLine ? 0x80 : 0)));
    b.Put<std::uint8_t>(p.classification);
    b.Put<std::int8_t>(static_cast<std::int8_t>(p.scanAngle));
    b.Put<std::uint8_t>(p.userData);
    b.Put<std::uint16_t>(p.pointSourceId);
  } else {
    // Return number bits 0-3, number of returns 4-7; then classification
    // flags 0-3, scanner channel 4-5, scan direction 6, edge 7.
    b.Put<std::uint8_t>(static_cast<std::uint8_t>((p.returnNumber & 15) | ((p.returnCount & 15) << 4)));
    b.Put<std::uint8_t>(static_cast<std::uint8_t>((p.classificationFlags & 15) | ((p.scannerChannel & 3) << 4) |
                                                  (p.scanDirection ? 0x40 : 0) | (p.edgeOfFlightLine ? 0x80 : 0)));
    b.Put<std::uint8_t>(p.classification);
    b.Put<std::uint8_t>(p.userData);
    b.Put<std::int16_t>(p.scanAngle);
    b.Put<std::uint16_t>(p.pointSourceId);
  }
  if (HasGpsTime(format)) b.Put<double>(p.gpsTime);
  if (HasRgb(format)) {
    b.Put<std::uint16_t>(p.red);
    b.Put<std::uint16_t>(p.green);
    b.Put<std::uint16_t>(p.blue);
  }
  if (HasNir(format)) b.Put<std::uint16_t>(p.nir);
  if (HasWavePacket(format)) {
    b.Put<std::uint8_t>(p.wavePacketIndex);
    b.Put<std::uint64_t>(p.waveformOffset);
    b.Put<std::uint32_t>(p.waveformSize);
    b.Put<float>(p.waveformLocation);
    b.Put<float>(p.dx);
    b.Put<float>(p.dy);
    b.Put<float>(p.dz);
  }
  std::string extra = p.extraBytes;
  extra.resize(extraBytes, '\0');
  b.PutRaw(extra);
  return b.text();
}

/// A VLR (54-byte header) or, with `extended`, an EVLR (60-byte header).
void PutRecord(const LasRecord& record, bool extended, int versionMinor, Bytes* b) {
  // LAS 1.0 called the reserved field the record signature, 0xAABB.
  b->Put<std::uint16_t>(versionMinor == 0 ? 0xAABB : 0);
  b->PutText(record.userId, 16);
  b->Put<std::uint16_t>(record.recordId);
  if (extended) {
    b->Put<std::uint64_t>(record.payload.size());
  } else {
    b->Put<std::uint16_t>(static_cast<std::uint16_t>(record.payload.size()));
  }
  b->PutText(record.description, 32);
  b->PutRaw(record.payload);
}

/// The Extra Bytes VLR ("struct EXTRA_BYTES", 192 bytes a descriptor)
/// describing `count` extra bytes, each an unsigned char (data type 1)
/// named "extra_k".
LasRecord ExtraBytesVlr(std::size_t count) {
  LasRecord record{"LASF_Spec", 4, "extra bytes", ""};
  for (std::size_t k = 0; k < count; ++k) {
    Bytes d;
    d.PutText("", 2);                  // reserved
    d.Put<std::uint8_t>(1);            // data type: unsigned char
    d.Put<std::uint8_t>(0);            // options
    d.PutText("extra_" + std::to_string(k), 32);
    d.PutText("", 4);                  // unused
    d.PutText("", 24);                 // no_data, deprecated1
    d.PutText("", 24);                 // min, deprecated2
    d.PutText("", 24);                 // max, deprecated3
    d.PutText("", 24);                 // scale, deprecated4
    d.PutText("", 24);                 // offset, deprecated5
    d.PutText("test byte", 32);        // description
    record.payload += d.text();
  }
  return record;
}

}  // namespace

std::size_t LasRecordLength(int format) {
  // The "Minimum PDRF Size" of each table.
  static const std::size_t kLengths[] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
  return kLengths[format];
}

int LasMaxFormat(int minor) {
  static const int kMax[] = {1, 1, 3, 5, 10};
  return kMax[minor];
}

std::vector<std::string> LasRecords(const LasFile& file) {
  std::vector<std::string> records;
  for (const LasPoint& p : file.points) records.push_back(Record(p, file.pointFormat, file.extraBytes));
  return records;
}

std::string WriteLas(const LasFile& file) {
  const int minor = file.versionMinor;
  const std::size_t headerSize = (minor <= 2 ? 227 : (minor == 3 ? 235 : 375)) + file.headerPadding;
  std::vector<LasRecord> vlrs = file.vlrs;
  if (file.describeExtraBytes) vlrs.push_back(ExtraBytesVlr(file.extraBytes));
  std::size_t vlrBytes = 0;
  for (const LasRecord& r : vlrs) vlrBytes += 54 + r.payload.size();
  const std::string signature = minor == 0 ? std::string("\xDD\xCC", 2) : std::string();
  const std::size_t pointOffset = headerSize + vlrBytes + signature.size() + file.bytesBeforePoints.size();
  const std::size_t recordLength = LasRecordLength(file.pointFormat) + file.extraBytes;
  const std::size_t pointEnd = pointOffset + file.points.size() * recordLength;

  // Counts by return and bounds, from the points.
  std::uint64_t byReturn[15] = {};
  double lo[3] = {0, 0, 0};
  double hi[3] = {0, 0, 0};
  for (std::size_t i = 0; i < file.points.size(); ++i) {
    const LasPoint& p = file.points[i];
    const int r = p.returnNumber & (file.pointFormat <= 5 ? 7 : 15);
    if (r >= 1) ++byReturn[r - 1];
    const std::int32_t values[3] = {p.x, p.y, p.z};
    for (int k = 0; k < 3; ++k) {
      const double c = values[k] * file.scale[k] + file.offset[k];
      lo[k] = i == 0 ? c : std::min(lo[k], c);
      hi[k] = i == 0 ? c : std::max(hi[k], c);
    }
  }
  const bool legacy = minor < 4 || (file.legacyCounts && file.pointFormat <= 5);
  const bool waveform = minor >= 3 && !file.waveformPackets.empty();
  std::size_t evlrCount = file.evlrs.size() + (waveform ? 1 : 0);

  Bytes b;
  b.PutText("LASF", 4);
  b.Put<std::uint16_t>(7);  // file source ID (LAS 1.0: reserved, any)
  b.Put<std::uint16_t>(static_cast<std::uint16_t>(waveform ? 2 : 0));  // global encoding: waveform internal
  b.Put<std::uint32_t>(0x01020304);  // project ID, GUID data 1
  b.Put<std::uint16_t>(0x0506);
  b.Put<std::uint16_t>(0x0708);
  b.PutText("GUIDdat4", 8);
  b.Put<std::uint8_t>(1);
  b.Put<std::uint8_t>(static_cast<std::uint8_t>(minor));
  b.PutText("invmap tests", 32);
  b.PutText("tests/support/las_writer", 32);
  b.Put<std::uint16_t>(331);
  b.Put<std::uint16_t>(2026);
  b.Put<std::uint16_t>(static_cast<std::uint16_t>(headerSize));
  b.Put<std::uint32_t>(static_cast<std::uint32_t>(pointOffset));
  b.Put<std::uint32_t>(static_cast<std::uint32_t>(vlrs.size()));
  b.Put<std::uint8_t>(static_cast<std::uint8_t>(file.pointFormat));
  b.Put<std::uint16_t>(static_cast<std::uint16_t>(recordLength));
  b.Put<std::uint32_t>(legacy ? static_cast<std::uint32_t>(file.points.size()) : 0);
  for (int r = 0; r < 5; ++r) b.Put<std::uint32_t>(legacy ? static_cast<std::uint32_t>(byReturn[r]) : 0);
  for (int k = 0; k < 3; ++k) b.Put<double>(file.scale[k]);
  for (int k = 0; k < 3; ++k) b.Put<double>(file.offset[k]);
  for (int k = 0; k < 3; ++k) {
    b.Put<double>(hi[k]);
    b.Put<double>(lo[k]);
  }
  if (minor >= 3) b.Put<std::uint64_t>(waveform ? pointEnd : 0);
  if (minor >= 4) {
    b.Put<std::uint64_t>(evlrCount > 0 ? pointEnd : 0);
    b.Put<std::uint32_t>(static_cast<std::uint32_t>(evlrCount));
    b.Put<std::uint64_t>(file.points.size());
    for (int r = 0; r < 15; ++r) b.Put<std::uint64_t>(byReturn[r]);
  }
  b.PutRaw(std::string(file.headerPadding, '\x5A'));
  for (const LasRecord& r : vlrs) PutRecord(r, false, minor, &b);
  b.PutRaw(signature);
  b.PutRaw(file.bytesBeforePoints);
  for (const std::string& record : LasRecords(file)) b.PutRaw(record);
  if (waveform) PutRecord({"LASF_Spec", 65535, "waveform data packets", file.waveformPackets}, true, minor, &b);
  if (minor >= 4) {
    for (const LasRecord& r : file.evlrs) PutRecord(r, true, minor, &b);
  }
  return b.text();
}

std::vector<LasPoint> RandomLasPoints(std::size_t count, int format, std::size_t extraBytes, std::int32_t extent,
                                      std::mt19937_64* random) {
  std::mt19937_64& rng = *random;
  const auto uniform = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  std::vector<LasPoint> points(count);
  const int maxReturn = format <= 5 ? 7 : 15;
  for (LasPoint& p : points) {
    p.x = uniform(-extent, extent);
    p.y = uniform(-extent, extent);
    p.z = uniform(-extent, extent);
    p.intensity = static_cast<std::uint16_t>(uniform(0, 65535));
    // Return 0 (not allowed, but found in files) included on purpose.
    p.returnNumber = uniform(0, maxReturn);
    p.returnCount = uniform(std::max(1, p.returnNumber), maxReturn);
    p.classificationFlags = uniform(0, 15);
    p.scannerChannel = uniform(0, 3);
    p.scanDirection = uniform(0, 1) == 1;
    p.edgeOfFlightLine = uniform(0, 1) == 1;
    p.classification = static_cast<std::uint8_t>(uniform(0, 255));
    p.scanAngle = static_cast<std::int16_t>(format <= 5 ? uniform(-90, 90) : uniform(-30000, 30000));
    p.userData = static_cast<std::uint8_t>(uniform(0, 255));
    p.pointSourceId = static_cast<std::uint16_t>(uniform(0, 65535));
    p.gpsTime = std::uniform_real_distribution<double>(0, 604800)(rng);
    p.red = static_cast<std::uint16_t>(uniform(0, 65535));
    p.green = static_cast<std::uint16_t>(uniform(0, 65535));
    p.blue = static_cast<std::uint16_t>(uniform(0, 65535));
    p.nir = static_cast<std::uint16_t>(uniform(0, 65535));
    p.wavePacketIndex = static_cast<std::uint8_t>(uniform(1, 3));
    p.waveformOffset = static_cast<std::uint64_t>(uniform(0, 1000)) * 60;
    p.waveformSize = 60;
    p.waveformLocation = static_cast<float>(uniform(0, 1000)) * 0.5F;
    p.dx = 0.25F;
    p.dy = -0.5F;
    p.dz = -1.0F;
    for (std::size_t k = 0; k < extraBytes; ++k) p.extraBytes.push_back(static_cast<char>(uniform(0, 255)));
  }
  return points;
}

}  // namespace invmap::testing
