#include "io/ply.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <utility>

#include "io/input_error.h"

namespace invmap::io {
namespace {

/// Longest header accepted: real headers are a few hundred bytes; the cap
/// stops a non-PLY file that starts with "ply" from being read whole.
constexpr std::int64_t kMaxHeaderBytes = std::int64_t{16} << 20;

/// Splits a line at spaces and tabs into `tokens` (views into `line`).
void SplitWhitespace(std::string_view line, std::vector<std::string_view>* tokens) {
  tokens->clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) tokens->push_back(line.substr(start, i - start));
  }
}

/// True for the six integer types (list counts must have one).
bool IsIntegerType(PlyType type) { return type != PlyType::Float32 && type != PlyType::Float64; }

/// Smallest and largest value of an integer type.
std::pair<std::int64_t, std::int64_t> IntegerRange(PlyType type) {
  switch (type) {
    case PlyType::Int8:
      return {-128, 127};
    case PlyType::UInt8:
      return {0, 255};
    case PlyType::Int16:
      return {-32768, 32767};
    case PlyType::UInt16:
      return {0, 65535};
    case PlyType::Int32:
      return {std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::max()};
    default:
      return {0, std::numeric_limits<std::uint32_t>::max()};
  }
}

/// Binary value of `type` at p, widened to double.
double DecodeValue(const char* p, PlyType type, bool bigEndian) {
  switch (type) {
    case PlyType::Int8:
      return static_cast<std::int8_t>(*p);
    case PlyType::UInt8:
      return static_cast<std::uint8_t>(*p);
    case PlyType::Int16:
      return LoadValue<std::int16_t>(p, bigEndian);
    case PlyType::UInt16:
      return LoadValue<std::uint16_t>(p, bigEndian);
    case PlyType::Int32:
      return LoadValue<std::int32_t>(p, bigEndian);
    case PlyType::UInt32:
      return LoadValue<std::uint32_t>(p, bigEndian);
    case PlyType::Float32:
      return LoadValue<float>(p, bigEndian);
    case PlyType::Float64:
      return LoadValue<double>(p, bigEndian);
  }
  return 0.0;
}

/// Smallest bytes a record of `element` can take: binary, every scalar and
/// every list count (lists may be empty); ascii, one character and one
/// separator per scalar or list count.
std::int64_t MinRecordBytes(const PlyElement& element, PlyFormat format) {
  // An ascii record is a line: a digit and its newline at least. (Counting
  // two bytes per property would reject a file with one short line by its
  // size, before the reader could name that line.)
  if (format == PlyFormat::Ascii) return 2;
  std::int64_t bytes = 0;
  for (const PlyProperty& property : element.properties) {
    bytes += PlyTypeSize(property.isList ? property.countType : property.type);
  }
  return bytes;
}

}  // namespace

std::string PlyPatchableCount(std::int64_t count) {
  const std::string digits = std::to_string(count);
  if (count < 0 || digits.size() > static_cast<std::size_t>(kPlyPatchableCountDigits)) {
    throw std::length_error("PLY record count " + digits + " does not fit the reserved digits");
  }
  std::string text = digits + "\ncomment ";
  text.append(static_cast<std::size_t>(kPlyPatchableCountBytes) - text.size(), ' ');
  return text;
}

int PlyTypeSize(PlyType type) {
  switch (type) {
    case PlyType::Int8:
    case PlyType::UInt8:
      return 1;
    case PlyType::Int16:
    case PlyType::UInt16:
      return 2;
    case PlyType::Int32:
    case PlyType::UInt32:
    case PlyType::Float32:
      return 4;
    case PlyType::Float64:
      return 8;
  }
  return 0;
}

const char* PlyTypeName(PlyType type) {
  static const char* const kNames[] = {"char", "uchar", "short", "ushort", "int", "uint", "float", "double"};
  return kNames[static_cast<int>(type)];
}

bool ParsePlyType(std::string_view name, PlyType* type) {
  static const char* const kSizedNames[] = {"int8",  "uint8",  "int16",   "uint16",
                                            "int32", "uint32", "float32", "float64"};
  for (int t = 0; t < 8; ++t) {
    if (name == PlyTypeName(static_cast<PlyType>(t)) || name == kSizedNames[t]) {
      *type = static_cast<PlyType>(t);
      return true;
    }
  }
  return false;
}

int PlyElement::FindProperty(std::string_view propertyName) const {
  for (std::size_t p = 0; p < properties.size(); ++p) {
    if (properties[p].name == propertyName) return static_cast<int>(p);
  }
  return -1;
}

int PlyHeader::FindElement(std::string_view elementName) const {
  for (std::size_t e = 0; e < elements.size(); ++e) {
    if (elements[e].name == elementName) return static_cast<int>(e);
  }
  return -1;
}

PlyReader::PlyReader(const std::string& path) : input_(path) { ParseHeader(); }

PlyReader::PlyReader(std::unique_ptr<std::istream> stream, const std::string& name) : input_(std::move(stream), name) {
  ParseHeader();
}

std::int64_t PlyReader::line() const { return header_.format == PlyFormat::Ascii ? input_.lineNumber() : 0; }

void PlyReader::ParseHeader() {
  const std::string& file = input_.name();
  std::string_view line;
  if (!input_.ReadLine(&line)) throw InputError(file, 0, "empty file");
  std::vector<std::string_view> tokens;
  SplitWhitespace(line, &tokens);
  if (tokens.size() != 1 || tokens[0] != "ply")
    throw InputError(file, 1, "not a PLY file (the first line is not 'ply')");
  header_.lines.emplace_back(line);
  bool haveFormat = false;
  bool ended = false;
  while (!ended) {
    if (input_.offset() > kMaxHeaderBytes)
      throw InputError(file, input_.lineNumber(), "no end_header in the first 16 MiB");
    if (!input_.ReadLine(&line)) throw InputError(file, input_.lineNumber(), "the header has no end_header line");
    const std::int64_t lineNo = input_.lineNumber();
    SplitWhitespace(line, &tokens);
    header_.lines.emplace_back(line);
    if (tokens.empty()) continue;
    const std::string_view keyword = tokens[0];
    if (keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "end_header") {
      ended = true;
    } else if (keyword == "format") {
      if (tokens.size() != 3) throw InputError(file, lineNo, "expected 'format <type> 1.0'");
      if (tokens[1] == "ascii") {
        header_.format = PlyFormat::Ascii;
      } else if (tokens[1] == "binary_little_endian") {
        header_.format = PlyFormat::BinaryLittleEndian;
      } else if (tokens[1] == "binary_big_endian") {
        header_.format = PlyFormat::BinaryBigEndian;
      } else {
        throw InputError(file, lineNo, "unknown PLY format '" + std::string(tokens[1]) + "'");
      }
      if (tokens[2] != "1.0" && tokens[2] != "1") {
        throw InputError(file, lineNo, "unsupported PLY version '" + std::string(tokens[2]) + "' (expected 1.0)");
      }
      haveFormat = true;
    } else if (keyword == "element") {
      std::int64_t count = 0;
      if (tokens.size() != 3) throw InputError(file, lineNo, "expected 'element <name> <count>'");
      if (!ParseInteger(tokens[2], &count) || count < 0) {
        throw InputError(file, lineNo, "bad element count '" + std::string(tokens[2]) + "'");
      }
      PlyElement element;
      element.name = std::string(tokens[1]);
      element.count = count;
      element.headerLine = header_.lines.size() - 1;
      header_.elements.push_back(std::move(element));
    } else if (keyword == "property") {
      if (header_.elements.empty()) throw InputError(file, lineNo, "property before any element");
      PlyProperty property;
      const bool isList = tokens.size() >= 2 && tokens[1] == "list";
      if (tokens.size() != (isList ? 5u : 3u)) {
        throw InputError(file, lineNo,
                         "expected 'property <type> <name>' or 'property list <count type> <type> <name>'");
      }
      const std::string_view typeName = tokens[isList ? 3 : 1];
      if (!ParsePlyType(typeName, &property.type)) {
        throw InputError(file, lineNo, "unknown property type '" + std::string(typeName) + "'");
      }
      if (isList) {
        if (!ParsePlyType(tokens[2], &property.countType) || !IsIntegerType(property.countType)) {
          throw InputError(file, lineNo, "list count type '" + std::string(tokens[2]) + "' is not an integer type");
        }
      }
      property.isList = isList;
      property.name = std::string(tokens.back());
      header_.elements.back().properties.push_back(std::move(property));
    } else {
      throw InputError(file, lineNo, "unknown header line '" + std::string(keyword) + "'");
    }
  }
  if (!haveFormat) throw InputError(file, input_.lineNumber(), "the header has no format line");
  header_.dataOffset = input_.offset();

  // Check the promised records against the bytes that follow the header
  // before any caller reserves memory for them.
  const std::int64_t available = input_.remaining();
  dataBytes_ = available;
  std::int64_t needed = 0;
  for (const PlyElement& element : header_.elements) {
    const std::int64_t minBytes = MinRecordBytes(element, header_.format);
    if (element.count > 0 && element.properties.empty()) {
      throw InputError(file, 0, "element '" + element.name + "' has records but no properties");
    }
    fixedRecordBytes_.push_back(minBytes);
    for (const PlyProperty& property : element.properties) {
      if (property.isList) fixedRecordBytes_.back() = -1;
    }
    if (available < 0 || element.count == 0) continue;
    // An ascii file may end without a newline after its last value.
    const std::int64_t budget = available + (header_.format == PlyFormat::Ascii ? 1 : 0) - needed;
    if (element.count > budget / minBytes) {
      throw InputError(file, 0,
                       "the header declares " + std::to_string(element.count) + " '" + element.name +
                           "' records (at least " + std::to_string(minBytes) + " bytes each), but only " +
                           std::to_string(available) + " bytes of data follow the header");
    }
    needed += element.count * minBytes;
  }
  if (header_.format == PlyFormat::Ascii) fixedRecordBytes_.assign(header_.elements.size(), -1);
}

void PlyReader::Truncated() const {
  const PlyElement& element = header_.elements[element_];
  throw InputError(input_.name(), header_.format == PlyFormat::Ascii ? input_.lineNumber() + 1 : 0,
                   "the file ends in '" + element.name + "' record " + std::to_string(record_) + " of " +
                       std::to_string(element.count) + " (truncated?)");
}

bool PlyReader::ReadRecord(PlyRecord* record, std::string* raw) {
  if (element_ >= header_.elements.size() || record_ >= header_.elements[element_].count) return false;
  const bool read = header_.format == PlyFormat::Ascii ? ReadAsciiRecord(record, raw) : ReadBinaryRecord(record, raw);
  ++record_;
  return read;
}

bool PlyReader::ReadBinaryRecord(PlyRecord* record, std::string* raw) {
  const PlyElement& element = header_.elements[element_];
  const bool bigEndian = header_.format == PlyFormat::BinaryBigEndian;
  record->values.clear();
  record->begin.clear();
  const std::int64_t fixed = fixedRecordBytes_[element_];
  if (fixed >= 0) {
    // Common case (vertices): one Fill for the whole record.
    if (!input_.Fill(static_cast<std::size_t>(fixed))) Truncated();
    const char* p = input_.data();
    for (const PlyProperty& property : element.properties) {
      record->begin.push_back(record->values.size());
      record->values.push_back(DecodeValue(p, property.type, bigEndian));
      p += PlyTypeSize(property.type);
    }
    record->begin.push_back(record->values.size());
    if (raw != nullptr) raw->append(input_.data(), static_cast<std::size_t>(fixed));
    input_.Consume(static_cast<std::size_t>(fixed));
    return true;
  }
  // Records with lists: Fill may move the buffer, so positions are offsets.
  std::size_t offset = 0;
  for (const PlyProperty& property : element.properties) {
    record->begin.push_back(record->values.size());
    if (!property.isList) {
      const std::size_t size = static_cast<std::size_t>(PlyTypeSize(property.type));
      if (!input_.Fill(offset + size)) Truncated();
      record->values.push_back(DecodeValue(input_.data() + offset, property.type, bigEndian));
      offset += size;
      continue;
    }
    const std::size_t countSize = static_cast<std::size_t>(PlyTypeSize(property.countType));
    if (!input_.Fill(offset + countSize)) Truncated();
    const double count = DecodeValue(input_.data() + offset, property.countType, bigEndian);
    offset += countSize;
    if (count < 0 || count > static_cast<double>(kMaxListEntries)) {
      throw InputError(input_.name(), 0,
                       "'" + element.name + "' record " + std::to_string(record_) + ": list '" + property.name +
                           "' has a bad length " + std::to_string(static_cast<std::int64_t>(count)));
    }
    const std::size_t entries = static_cast<std::size_t>(count);
    const std::size_t size = static_cast<std::size_t>(PlyTypeSize(property.type));
    if (!input_.Fill(offset + entries * size)) Truncated();
    for (std::size_t i = 0; i < entries; ++i) {
      record->values.push_back(DecodeValue(input_.data() + offset, property.type, bigEndian));
      offset += size;
    }
  }
  record->begin.push_back(record->values.size());
  if (raw != nullptr) raw->append(input_.data(), offset);
  input_.Consume(offset);
  return true;
}

bool PlyReader::ReadAsciiRecord(PlyRecord* record, std::string* raw) {
  const PlyElement& element = header_.elements[element_];
  std::string_view line;
  std::string_view rawLine;
  std::vector<std::string_view> tokens;
  do {
    if (!input_.ReadLine(&line, &rawLine)) Truncated();
    SplitWhitespace(line, &tokens);
  } while (tokens.empty());
  const std::int64_t lineNo = input_.lineNumber();
  const auto fail = [&](const std::string& what) {
    throw InputError(input_.name(), lineNo, "'" + element.name + "' record " + std::to_string(record_) + ": " + what);
  };
  // Parses tokens[t] as a value of `type`; integers must fit the type.
  const auto parse = [&](std::size_t t, PlyType type, const PlyProperty& property) {
    if (t >= tokens.size()) fail("too few values: none for property '" + property.name + "'");
    if (IsIntegerType(type)) {
      std::int64_t value = 0;
      const auto range = IntegerRange(type);
      if (!ParseInteger(tokens[t], &value) || value < range.first || value > range.second) {
        fail("'" + std::string(tokens[t]) + "' is not a valid " + PlyTypeName(type) + " for property '" +
             property.name + "'");
      }
      return static_cast<double>(value);
    }
    double value = 0.0;
    if (!ParseDouble(tokens[t], &value)) {
      fail("'" + std::string(tokens[t]) + "' is not a number (property '" + property.name + "')");
    }
    return value;
  };
  record->values.clear();
  record->begin.clear();
  std::size_t t = 0;
  for (const PlyProperty& property : element.properties) {
    record->begin.push_back(record->values.size());
    if (!property.isList) {
      record->values.push_back(parse(t++, property.type, property));
      continue;
    }
    const double count = parse(t++, property.countType, property);
    if (count < 0 || count > static_cast<double>(kMaxListEntries)) {
      fail("list '" + property.name + "' has a bad length " + std::string(tokens[t - 1]));
    }
    for (std::int64_t i = 0; i < static_cast<std::int64_t>(count); ++i) {
      record->values.push_back(parse(t++, property.type, property));
    }
  }
  record->begin.push_back(record->values.size());
  if (t != tokens.size()) {
    fail("too many values: " + std::to_string(tokens.size()) + " on the line, " + std::to_string(t) +
         " expected (one record per line)");
  }
  if (raw != nullptr) {
    raw->append(rawLine.data(), rawLine.size());
    if (rawLine.empty() || rawLine.back() != '\n') raw->push_back('\n');
  }
  return true;
}

void PlyReader::NextElement() {
  if (element_ >= header_.elements.size()) return;
  const std::int64_t left = header_.elements[element_].count - record_;
  const std::int64_t fixed = fixedRecordBytes_[element_];
  if (fixed >= 0) {
    // left * fixed was checked against the file size when it is known; in
    // steps it cannot overflow when it is not.
    for (std::int64_t done = 0; done < left;) {
      const std::int64_t step = std::min<std::int64_t>(left - done, std::int64_t{1} << 20);
      if (!input_.Skip(static_cast<std::uint64_t>(step * fixed))) {
        record_ += done;
        Truncated();
      }
      done += step;
    }
  } else {
    PlyRecord scratch;
    while (ReadRecord(&scratch)) {
    }
  }
  ++element_;
  record_ = 0;
}

void PlyReader::SkipToElement(std::size_t index) {
  while (element_ < index && element_ < header_.elements.size()) NextElement();
}

void PlyReader::ExpectEnd() {
  SkipToElement(header_.elements.size());
  const auto fail = [&](std::int64_t line) {
    std::string declared;
    for (const PlyElement& element : header_.elements) {
      declared += (declared.empty() ? "" : ", ") + std::to_string(element.count) + " '" + element.name + "'";
    }
    throw InputError(input_.name(), line,
                     "data after the last record: the header declares " + declared +
                         " records, and the file holds more");
  };
  if (header_.format == PlyFormat::Ascii) {
    std::string_view line;
    while (input_.ReadLine(&line)) {
      if (line.find_first_not_of(" \t\r") != std::string_view::npos) fail(input_.lineNumber());
    }
    return;
  }
  while (input_.Fill(1) || input_.available() > 0) {
    const std::string_view bytes(input_.data(), input_.available());
    if (bytes.find_first_not_of(" \t\r\n") != std::string_view::npos) fail(0);
    input_.Consume(bytes.size());
  }
}

}  // namespace invmap::io
