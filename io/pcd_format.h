// The Point Cloud Library's PCD format (versions 0.5 to 0.7): the header
// (FIELDS, SIZE, TYPE, COUNT, WIDTH, HEIGHT, VIEWPOINT, POINTS, DATA) and
// the layout of a point in each encoding (ascii, binary,
// binary_compressed), checked before the point reader streams the data and
// kept so that trim can write the kept points in the same encoding
// (docs/point-clouds.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "io/file_io.h"

namespace invmap::io {

/// How a PCD file stores its points (the DATA line).
enum class PcdEncoding : std::uint8_t {
  Ascii,             ///< one point a line, the values separated by spaces
  Binary,            ///< records of every field's values, point after point
  BinaryCompressed,  ///< one LZF block of every field's column, "_" fields left out
};

/// One field of the header: COUNT values of TYPE and SIZE per point.
struct PcdField {
  std::string name;
  char type = 'F';             ///< 'I' signed, 'U' unsigned integer, 'F' floating point.
  std::size_t size = 4;        ///< Bytes of one value: 1, 2, 4 or 8 (F: 4 or 8).
  std::size_t count = 1;       ///< Values per point.
  std::size_t offset = 0;      ///< Binary: byte offset of the field in a record.
  std::size_t firstValue = 0;  ///< Ascii: index of the field's first value on a line.

  /// Bytes of the field's values of one point.
  std::size_t bytes() const { return size * count; }
  /// PCL's padding field "_": its bytes are not part of binary_compressed data.
  bool isPadding() const { return name == "_"; }
};

/// What a PCD header says, checked: the fields, the point count and where
/// the data starts, and the header lines trim writes back.
struct PcdLayout {
  PcdEncoding encoding = PcdEncoding::Ascii;
  /// The header lines verbatim, each with its terminator, up to and with DATA.
  std::vector<std::string> headerLines;
  /// Indices in headerLines of the WIDTH, HEIGHT and POINTS lines, -1 when absent.
  int widthLine = -1;
  int heightLine = -1;
  int pointsLine = -1;
  std::vector<PcdField> fields;
  /// Indices in `fields` of x, y and z (z: -1 when there is none).
  int coordinateField[3] = {-1, -1, -1};
  std::size_t pointBytes = 0;        ///< Binary: bytes of a record (every field).
  std::size_t storedPointBytes = 0;  ///< Binary_compressed: bytes of a point without "_" fields.
  std::size_t valuesPerLine = 0;     ///< Ascii: values on a point's line.
  std::uint64_t width = 0;
  std::uint64_t height = 1;
  std::uint64_t points = 0;    ///< WIDTH x HEIGHT.
  std::uint64_t dataOffset = 0;  ///< File offset of the first byte after the DATA line.
};

/// Most fields a PCD file may have: a binary_compressed reader keeps an
/// 8 KiB LZF window per field, which this bounds.
inline constexpr std::size_t kMaxPcdFields = 4096;
/// Most bytes of one point (every field's values).
inline constexpr std::size_t kMaxPcdPointBytes = std::size_t{16} << 20;

/// Reads and checks a PCD header from the start of `input` (named `path`)
/// and consumes it through the DATA line. Throws InputError naming the
/// file and line for an unknown or malformed header line, fields without
/// x and y, counts that disagree (WIDTH x HEIGHT != POINTS), a field type
/// and size PCD does not have, or an unknown DATA encoding.
PcdLayout ReadPcdHeader(InputBuffer& input, const std::string& path);

/// Value of a binary PCD value of `type` and `size` at p (little-endian,
/// unaligned), widened to double.
double PcdValue(const char* p, char type, std::size_t size);

/// A "KEYWORD count" header line that fits the same bytes whatever the
/// count, for a writer that learns the count at the end: "WIDTH 12\n#"
/// and spaces taking up the digits the count does not use (a comment line;
/// the caller writes its terminator). Throws std::length_error for a count
/// of more than 15 digits.
std::string PcdPatchableCountLine(const std::string& keyword, std::uint64_t count);

/// True for a header line "#" followed by spaces only: the padding of
/// PcdPatchableCountLine, which trim drops from its input's header.
bool IsPcdPaddingLine(const std::string& line);

}  // namespace invmap::io
