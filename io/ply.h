// General PLY reading: the header (ascii, binary_little_endian,
// binary_big_endian; elements with scalar and list properties; comments and
// obj_info) and a record-at-a-time stream over the elements, which the point
// reader, the mesh reader and trim build on. A header that promises more
// data than the file holds is rejected before anything is reserved.
#pragma once

#include <cstddef>
#include <cstdint>
#include <istream>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "io/file_io.h"

namespace invmap::io {

/// Storage of a PLY data section.
enum class PlyFormat : std::uint8_t { Ascii, BinaryLittleEndian, BinaryBigEndian };

/// Value types of PLY properties. Each has two spellings in headers:
/// char/int8, uchar/uint8, short/int16, ushort/uint16, int/int32,
/// uint/uint32, float/float32, double/float64.
enum class PlyType : std::uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

/// Bytes of one binary value of `type`.
int PlyTypeSize(PlyType type);
/// The classic spelling of `type` ("char", "uchar", ..., "double").
const char* PlyTypeName(PlyType type);
/// Parses either spelling of a type name; false when `name` is not one.
bool ParsePlyType(std::string_view name, PlyType* type);

/// Digits of a record count that a streaming writer writes before it knows
/// the count and patches at the end: 12 digits allow up to 10^12 - 1 records.
inline constexpr int kPlyPatchableCountDigits = 12;

/// Bytes of PlyPatchableCount's text, whatever the count.
inline constexpr int kPlyPatchableCountBytes = kPlyPatchableCountDigits + 9;

/// A record count that fits the same bytes whatever its value, to end an
/// "element NAME " line: the plain decimal count, the line's end, then a
/// comment line ("comment" and spaces) that takes up the digits the count
/// does not use ("2\ncomment" and 11 spaces). The caller writes the
/// comment line's own "\n" after it. (Zero-padded digits would read as the
/// count too, but look like a fault: "element vertex 000000000002".)
/// Throws std::length_error when the count does not fit.
std::string PlyPatchableCount(std::int64_t count);

/// One property of an element: a scalar, or a list (a count, then that many values).
struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;  ///< Type of the value (of each entry for a list).
  bool isList = false;
  PlyType countType = PlyType::UInt8;  ///< List only: type of the entry count (an integer type).
};

/// One element of the header: a name, a record count and the properties of
/// each record, in file order.
struct PlyElement {
  std::string name;
  std::int64_t count = 0;
  std::vector<PlyProperty> properties;
  /// Index in PlyHeader::lines of this element's "element" line; its
  /// properties (and any comments between them) follow up to the next
  /// element line or end_header.
  std::size_t headerLine = 0;

  /// Index of the property called `name`, -1 when there is none.
  int FindProperty(std::string_view propertyName) const;
};

/// A parsed PLY header.
struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;
  /// The header lines verbatim, "ply" to "end_header", without terminators.
  std::vector<std::string> lines;
  /// Bytes from the start of the file to the first data byte.
  std::int64_t dataOffset = 0;

  /// Index of the element called `name`, -1 when there is none.
  int FindElement(std::string_view elementName) const;
};

/// One decoded record. Every value is widened to double, which holds all
/// PLY types exactly. A scalar property contributes one value, a list
/// property its entries (its count is the span's length).
struct PlyRecord {
  std::vector<double> values;
  /// Property p's values are values[begin[p] .. begin[p + 1]); size =
  /// properties + 1.
  std::vector<std::size_t> begin;

  /// Value of scalar property p.
  double Scalar(std::size_t p) const { return values[begin[p]]; }
  /// Number of entries of list property p.
  std::size_t ListSize(std::size_t p) const { return begin[p + 1] - begin[p]; }
  /// First entry of list property p (ListSize(p) of them).
  const double* List(std::size_t p) const { return values.data() + begin[p]; }
};

/// Streams the records of a PLY file, element after element in file order.
/// Ascii records are one per line (blank lines are skipped); errors give
/// the line. Binary errors give the element and record index. All errors
/// are InputError naming the file.
class PlyReader {
 public:
  /// Longest list accepted, in entries: a longer one is a corrupt count,
  /// refused so that memory stays bounded.
  static constexpr std::int64_t kMaxListEntries = std::int64_t{1} << 24;

  /// Opens `path` and parses its header.
  explicit PlyReader(const std::string& path);
  /// Reads `stream` (owned), named `name` in messages. The size checks of
  /// the header need a seekable stream; otherwise a lying header is found
  /// when the data runs out.
  PlyReader(std::unique_ptr<std::istream> stream, const std::string& name);

  /// The parsed header.
  const PlyHeader& header() const { return header_; }
  /// File name used in messages.
  const std::string& name() const { return input_.name(); }
  /// Index of the element whose records ReadRecord returns;
  /// header().elements.size() once all are done.
  std::size_t element() const { return element_; }
  /// Index within the current element of the next record.
  std::int64_t recordIndex() const { return record_; }
  /// 1-based line of the last ascii record read (0 for binary files).
  std::int64_t line() const;
  /// True when the header's counts were checked against the input size (a
  /// file or a seekable stream): only then may a caller reserve memory for
  /// all the records a header declares.
  bool countsChecked() const { return input_.size() >= 0; }
  /// Bytes of data after the header (what the counts were checked
  /// against); -1 when the input's size is unknown.
  std::int64_t dataBytes() const { return dataBytes_; }

  /// Reads the next record of the current element into `record` and, when
  /// `raw` is not null, appends the record's bytes to it verbatim (ascii:
  /// its line with terminator; "\n" is added to a last line without one).
  /// Returns false when the current element has no records left.
  bool ReadRecord(PlyRecord* record, std::string* raw = nullptr);
  /// Skips the rest of the current element and moves to the next.
  void NextElement();
  /// Skips forward to the first record of element `index` (>= element()).
  void SkipToElement(std::size_t index);
  /// Skips the elements left, then throws InputError when data follows the
  /// last record (a header that declares fewer records than the file
  /// holds, whose extra records would be dropped unseen): ascii, the first
  /// line that is not blank, by its number; binary, any byte but ASCII
  /// whitespace (a newline some writers add).
  void ExpectEnd();

 private:
  /// Parses the header lines and checks the counts against the file size.
  void ParseHeader();
  /// Throws "file ends inside record r of element e" (the data is truncated).
  [[noreturn]] void Truncated() const;
  /// ReadRecord for the binary formats.
  bool ReadBinaryRecord(PlyRecord* record, std::string* raw);
  /// ReadRecord for ascii: one record per non-blank line.
  bool ReadAsciiRecord(PlyRecord* record, std::string* raw);

  InputBuffer input_;        ///< The file, positioned at the next record.
  PlyHeader header_;         ///< The parsed header.
  std::size_t element_ = 0;  ///< See element().
  std::int64_t record_ = 0;  ///< See recordIndex().
  /// Per element: bytes of a binary record, or -1 when it has a list.
  std::vector<std::int64_t> fixedRecordBytes_;
  std::int64_t dataBytes_ = -1;  ///< See dataBytes().
};

}  // namespace invmap::io
