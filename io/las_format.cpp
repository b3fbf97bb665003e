#include "io/las_format.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "io/input_error.h"
#include "io/positional_file.h"

namespace invmap::io {
namespace las {

std::size_t StandardHeaderSize(int minor) { return minor <= 2 ? 227 : (minor == 3 ? 235 : 375); }

std::size_t MinimumRecordLength(int format) {
  // Formats 0-5 share a 20-byte core (6-10 a 30-byte one with GPS time);
  // GPS time adds 8 bytes, RGB 6, NIR 2, a wave packet 29.
  static constexpr std::size_t kLengths[11] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
  return kLengths[format];
}

}  // namespace las
namespace {

template <class T>
T Load(const char* p) {
  return LoadValue<T>(p, false);
}

/// A double as %g writes it ("0", "nan", "1e+300").
std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

/// "x", "y" or "z".
const char* AxisName(int axis) { return axis == 0 ? "x" : (axis == 1 ? "y" : "z"); }

/// A fixed-length char field as text for a message, up to its first NUL;
/// bytes that are not printable ASCII (a corrupt file's) show as '?'.
std::string FixedText(const char* p, std::size_t length) {
  std::string text;
  for (std::size_t n = 0; n < length && p[n] != '\0'; ++n) text.push_back(p[n] >= ' ' && p[n] <= '~' ? p[n] : '?');
  return text;
}

/// The variable length records between the header and the point records:
/// each must end before the point records start. A LASzip record means the
/// points are compressed.
void ReadVlrs(InputBuffer& input, const std::string& path, std::uint32_t count, std::uint64_t headerSize,
              std::uint64_t pointDataOffset) {
  std::uint64_t position = headerSize;
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::string which = "variable length record " + std::to_string(i + 1) + " of " + std::to_string(count);
    if (pointDataOffset - position < las::kVlrHeaderBytes) {
      throw InputError(path, 0,
                       which + " starts at byte " + std::to_string(position) +
                           ", too close to the point data at byte " + std::to_string(pointDataOffset) +
                           " to hold its header");
    }
    if (!input.Fill(las::kVlrHeaderBytes)) throw InputError(path, 0, "the file ends inside " + which);
    const std::string user = FixedText(input.data() + 2, 16);
    const auto recordId = Load<std::uint16_t>(input.data() + 18);
    const auto length = Load<std::uint16_t>(input.data() + 20);
    if (user == "laszip encoded" && recordId == 22204) {
      throw InputError(path, 0, "the points are compressed (a LASzip record): " + LazRefusal());
    }
    position += las::kVlrHeaderBytes + length;
    if (position > pointDataOffset) {
      throw InputError(path, 0,
                       which + " (user '" + user + "', record " + std::to_string(recordId) + ") ends at byte " +
                           std::to_string(position) + ", past the start of the point data at byte " +
                           std::to_string(pointDataOffset));
    }
    input.Consume(las::kVlrHeaderBytes);
    if (!input.Skip(length)) throw InputError(path, 0, "the file ends inside " + which);
  }
  if (!input.Skip(pointDataOffset - position)) throw InputError(path, 0, "the file ends before its point data");
}

/// The extended variable length records of a LAS 1.4 file: each header and
/// payload must lie in the file, after the point records.
void CheckEvlrs(const LasLayout& layout) {
  if (layout.evlrCount == 0) return;
  const std::string& path = layout.path;
  if (layout.evlrStart < layout.pointDataEnd()) {
    throw InputError(path, 0,
                     "the first extended variable length record (byte " + std::to_string(layout.evlrStart) +
                         ") is not after the point records (bytes " + std::to_string(layout.pointDataOffset) + " to " +
                         std::to_string(layout.pointDataEnd()) + ")");
  }
  const PositionalFile file(path);
  std::uint64_t position = layout.evlrStart;
  for (std::uint32_t i = 0; i < layout.evlrCount; ++i) {
    const std::string which =
        "extended variable length record " + std::to_string(i + 1) + " of " + std::to_string(layout.evlrCount);
    char header[las::kEvlrHeaderBytes];
    if (layout.fileSize - position < las::kEvlrHeaderBytes || file.ReadAt(position, header, sizeof header) != sizeof header) {
      throw InputError(path, 0, which + " at byte " + std::to_string(position) + " runs past the end of the file");
    }
    const auto length = Load<std::uint64_t>(header + 20);
    if (length > layout.fileSize - position - las::kEvlrHeaderBytes) {
      throw InputError(path, 0,
                       which + " (user '" + FixedText(header + 2, 16) + "', record " +
                           std::to_string(Load<std::uint16_t>(header + 18)) + ") of " + std::to_string(length) +
                           " bytes runs past the end of the file");
    }
    position += las::kEvlrHeaderBytes + length;
  }
}

}  // namespace

std::string LazRefusal() {
  return "compressed LAZ is not supported; decompress it to LAS first, for example with "
         "'laszip -i in.laz -o out.las' or 'pdal translate in.laz out.las'";
}

LasLayout ReadLasHeader(InputBuffer& input, const std::string& path) {
  if (input.size() < 0) throw InputError(path, 0, "a LAS file must be a regular file (its size is needed)");
  LasLayout layout;
  layout.path = path;
  layout.fileSize = static_cast<std::uint64_t>(input.size());
  if (!input.Fill(4) || std::memcmp(input.data(), "LASF", 4) != 0) {
    throw InputError(path, 0, "not a LAS file: it does not start with 'LASF'");
  }
  if (!input.Fill(las::StandardHeaderSize(0))) {
    throw InputError(path, 0,
                     "the file ends inside the LAS header (" + std::to_string(layout.fileSize) +
                         " bytes; a header has at least 227)");
  }
  const auto formatByte = static_cast<unsigned char>(input.data()[las::kPointFormat]);
  // LASzip marks compressed points by setting the top bits of the format.
  if ((formatByte & 0xC0) != 0) {
    throw InputError(path, 0,
                     "point data record format byte " + std::to_string(formatByte) +
                         " marks compressed points: " + LazRefusal());
  }
  const int major = static_cast<unsigned char>(input.data()[las::kVersionMajor]);
  const int minor = static_cast<unsigned char>(input.data()[las::kVersionMinor]);
  if (major != 1 || minor > 4) {
    throw InputError(path, 0,
                     "LAS version " + std::to_string(major) + "." + std::to_string(minor) +
                         " is not supported (1.0 to 1.4 are)");
  }
  layout.versionMinor = minor;
  const std::size_t headerSize = Load<std::uint16_t>(input.data() + las::kHeaderSize);
  if (headerSize < las::StandardHeaderSize(minor)) {
    throw InputError(path, 0,
                     "header size " + std::to_string(headerSize) + " is smaller than LAS 1." + std::to_string(minor) +
                         "'s " + std::to_string(las::StandardHeaderSize(minor)) + " bytes");
  }
  if (!input.Fill(headerSize)) {
    throw InputError(path, 0,
                     "the file ends inside the header (header size " + std::to_string(headerSize) + ", file " +
                         std::to_string(layout.fileSize) + " bytes)");
  }
  const char* h = input.data();
  if (formatByte > 10) {
    throw InputError(path, 0, "unknown point data record format " + std::to_string(formatByte) + " (LAS has 0 to 10)");
  }
  layout.pointFormat = formatByte;
  layout.recordLength = Load<std::uint16_t>(h + las::kRecordLength);
  if (layout.recordLength < las::MinimumRecordLength(layout.pointFormat)) {
    throw InputError(path, 0,
                     "point data record length " + std::to_string(layout.recordLength) + " is shorter than format " +
                         std::to_string(layout.pointFormat) + "'s " +
                         std::to_string(las::MinimumRecordLength(layout.pointFormat)) + " bytes");
  }
  for (int axis = 0; axis < 3; ++axis) {
    layout.scale[axis] = Load<double>(h + las::kScale + 8 * axis);
    layout.offset[axis] = Load<double>(h + las::kOffset + 8 * axis);
    if (!std::isfinite(layout.scale[axis]) || layout.scale[axis] == 0.0) {
      throw InputError(path, 0, std::string(AxisName(axis)) + " scale factor is " + Number(layout.scale[axis]));
    }
    if (!std::isfinite(layout.offset[axis])) {
      throw InputError(path, 0, std::string(AxisName(axis)) + " offset is " + Number(layout.offset[axis]));
    }
  }
  const auto legacyCount = Load<std::uint32_t>(h + las::kLegacyPointCount);
  layout.pointCount = legacyCount;
  if (minor >= 3) layout.waveformStart = Load<std::uint64_t>(h + las::kWaveformStart);
  if (minor == 4) {
    layout.pointCount = Load<std::uint64_t>(h + las::kPointCount);
    // A reader that knows only the legacy count would see other points:
    // such a file needs repair, not a guess.
    if (legacyCount != 0 && legacyCount != layout.pointCount) {
      throw InputError(path, 0,
                       "the legacy point count (" + std::to_string(legacyCount) + ") disagrees with the point count (" +
                           std::to_string(layout.pointCount) + ")");
    }
    layout.legacyCounts = legacyCount != 0;
    layout.evlrStart = Load<std::uint64_t>(h + las::kEvlrStart);
    layout.evlrCount = Load<std::uint32_t>(h + las::kEvlrCount);
  }
  layout.pointDataOffset = Load<std::uint32_t>(h + las::kPointDataOffset);
  const auto vlrCount = Load<std::uint32_t>(h + las::kVlrCount);
  if (layout.pointDataOffset < headerSize) {
    throw InputError(path, 0,
                     "offset to point data (" + std::to_string(layout.pointDataOffset) + ") lies inside the " +
                         std::to_string(headerSize) + "-byte header");
  }
  if (layout.pointDataOffset > layout.fileSize ||
      layout.pointCount > (layout.fileSize - layout.pointDataOffset) / layout.recordLength) {
    throw InputError(path, 0,
                     "the header's " + std::to_string(layout.pointCount) + " point records of " +
                         std::to_string(layout.recordLength) + " bytes from byte " +
                         std::to_string(layout.pointDataOffset) + " do not fit in the file's " +
                         std::to_string(layout.fileSize) + " bytes");
  }
  if (layout.waveformStart != 0 &&
      (layout.waveformStart < layout.pointDataEnd() ||
       layout.waveformStart > layout.fileSize - std::min<std::uint64_t>(layout.fileSize, las::kEvlrHeaderBytes))) {
    throw InputError(path, 0,
                     "the waveform data packet record's start (byte " + std::to_string(layout.waveformStart) +
                         ") is not between the point records' end (byte " + std::to_string(layout.pointDataEnd()) +
                         ") and the file's end");
  }
  CheckEvlrs(layout);
  input.Consume(headerSize);
  ReadVlrs(input, path, vlrCount, headerSize, layout.pointDataOffset);
  return layout;
}

}  // namespace invmap::io
