#include "io/pcd_format.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string_view>

#include "io/input_error.h"

namespace invmap::io {
namespace {

/// Most header bytes before the DATA line: a header is a few hundred bytes,
/// so more is not a PCD file, and refusing it keeps memory bounded.
constexpr std::int64_t kMaxHeaderBytes = std::int64_t{16} << 20;

/// Digits PcdPatchableCountLine leaves room for.
constexpr std::size_t kPatchableDigits = 15;

/// The fields of a line separated by spaces and tabs.
std::vector<std::string_view> Tokens(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
  return tokens;
}

/// True when PCD has values of `type` and `size` (PCL's field types).
bool IsPcdType(char type, std::size_t size) {
  if (type == 'F') return size == 4 || size == 8;
  return (type == 'I' || type == 'U') && (size == 1 || size == 2 || size == 4 || size == 8);
}

/// Parses the header line by line; see ReadPcdHeader.
class HeaderParser {
 public:
  HeaderParser(InputBuffer& input, const std::string& path) : input_(input), path_(path) {}

  PcdLayout Parse() {
    std::string_view line;
    std::string_view raw;
    for (;;) {
      if (input_.offset() > kMaxHeaderBytes) Fail(input_.lineNumber(), "no DATA line in the first 16 MiB");
      if (!input_.ReadLine(&line, &raw)) {
        Fail(input_.lineNumber(), input_.lineNumber() == 0 ? "empty file" : "the header has no DATA line");
      }
      lineNumber_ = input_.lineNumber();
      layout_.headerLines.emplace_back(raw);
      if (raw.back() != '\n') layout_.headerLines.back().push_back('\n');
      const std::vector<std::string_view> tokens = Tokens(line);
      if (tokens.empty() || tokens[0][0] == '#') continue;
      if (HandleLine(tokens)) break;
    }
    layout_.dataOffset = static_cast<std::uint64_t>(input_.offset());
    Finish();
    return layout_;
  }

 private:
  [[noreturn]] void Fail(std::int64_t line, const std::string& what) const { throw InputError(path_, line, what); }
  [[noreturn]] void Fail(const std::string& what) const { Fail(lineNumber_, what); }

  /// Handles one header line; true for the DATA line, which ends the header.
  bool HandleLine(const std::vector<std::string_view>& tokens) {
    const std::string keyword(tokens[0]);
    const std::size_t values = tokens.size() - 1;
    if (keyword == "DATA") {
      if (values != 1) Fail("expected 'DATA ascii', 'DATA binary' or 'DATA binary_compressed'");
      if (tokens[1] == "ascii") {
        layout_.encoding = PcdEncoding::Ascii;
      } else if (tokens[1] == "binary") {
        layout_.encoding = PcdEncoding::Binary;
      } else if (tokens[1] == "binary_compressed") {
        layout_.encoding = PcdEncoding::BinaryCompressed;
      } else {
        Fail("unknown DATA encoding '" + std::string(tokens[1]) + "' (expected ascii, binary or binary_compressed)");
      }
      return true;
    }
    if (keyword != "VERSION" && !seen_.insert(keyword == "COLUMNS" ? "FIELDS" : keyword)) {
      Fail("a second " + keyword + " line");
    }
    if (keyword == "VERSION") return false;
    if (keyword == "FIELDS" || keyword == "COLUMNS") {
      if (values == 0) Fail("FIELDS names no field");
      if (values > kMaxPcdFields) Fail(std::to_string(values) + " fields (at most " + std::to_string(kMaxPcdFields) + ")");
      fieldsLine_ = lineNumber_;
      layout_.fields.resize(values);
      for (std::size_t i = 0; i < values; ++i) layout_.fields[i].name = std::string(tokens[i + 1]);
      return false;
    }
    if (keyword == "SIZE" || keyword == "TYPE" || keyword == "COUNT") {
      if (layout_.fields.empty()) Fail(keyword + " before FIELDS");
      if (values != layout_.fields.size()) {
        Fail(keyword + " has " + std::to_string(values) + " entries for " + std::to_string(layout_.fields.size()) +
             " fields");
      }
      for (std::size_t i = 0; i < values; ++i) SetFieldEntry(keyword, tokens[i + 1], &layout_.fields[i]);
      if (keyword == "SIZE") sizeLine_ = lineNumber_;
      if (keyword == "TYPE") typeLine_ = lineNumber_;
      return false;
    }
    if (keyword == "WIDTH" || keyword == "HEIGHT" || keyword == "POINTS") {
      std::int64_t value = 0;
      if (values != 1 || !ParseInteger(tokens[1], &value) || value < 0) Fail("expected '" + keyword + " <count>'");
      const int index = static_cast<int>(layout_.headerLines.size()) - 1;
      if (keyword == "WIDTH") {
        layout_.width = static_cast<std::uint64_t>(value);
        layout_.widthLine = index;
      } else if (keyword == "HEIGHT") {
        layout_.height = static_cast<std::uint64_t>(value);
        layout_.heightLine = index;
      } else {
        layout_.points = static_cast<std::uint64_t>(value);
        layout_.pointsLine = index;
      }
      return false;
    }
    if (keyword == "VIEWPOINT") {
      double number = 0.0;
      if (values != 7) Fail("VIEWPOINT needs 7 numbers (tx ty tz qw qx qy qz)");
      for (std::size_t i = 1; i <= values; ++i) {
        if (!ParseDouble(tokens[i], &number)) Fail("VIEWPOINT: '" + std::string(tokens[i]) + "' is not a number");
      }
      return false;
    }
    Fail("unknown header line '" + keyword + "'");
  }

  /// Sets the SIZE, TYPE or COUNT entry of `field` from `token`.
  void SetFieldEntry(const std::string& keyword, std::string_view token, PcdField* field) const {
    if (keyword == "TYPE") {
      if (token.size() != 1 || (token[0] != 'I' && token[0] != 'U' && token[0] != 'F')) {
        Fail("field '" + field->name + "': TYPE '" + std::string(token) + "' is not I, U or F");
      }
      field->type = token[0];
      return;
    }
    std::int64_t value = 0;
    if (!ParseInteger(token, &value) || value < 1 || static_cast<std::uint64_t>(value) > kMaxPcdPointBytes) {
      Fail("field '" + field->name + "': " + keyword + " '" + std::string(token) + "' is not a count from 1 to " +
           std::to_string(kMaxPcdPointBytes));
    }
    (keyword == "SIZE" ? field->size : field->count) = static_cast<std::size_t>(value);
  }

  /// Checks the header as a whole and derives the record layout.
  void Finish() {
    if (layout_.fields.empty()) Fail("the header has no FIELDS line");
    if (sizeLine_ == 0) Fail("the header has no SIZE line");
    if (typeLine_ == 0) Fail("the header has no TYPE line");
    std::size_t offset = 0;
    std::size_t value = 0;
    std::size_t stored = 0;
    const char* const names[3] = {"x", "y", "z"};
    for (std::size_t i = 0; i < layout_.fields.size(); ++i) {
      PcdField& field = layout_.fields[i];
      if (!IsPcdType(field.type, field.size)) {
        Fail(typeLine_, "field '" + field.name + "': TYPE " + field.type + " of SIZE " + std::to_string(field.size) +
                            " is not a PCD type");
      }
      if (field.count > kMaxPcdPointBytes / field.size || offset + field.bytes() > kMaxPcdPointBytes) {
        Fail(sizeLine_, "a point of more than " + std::to_string(kMaxPcdPointBytes) + " bytes");
      }
      field.offset = offset;
      field.firstValue = value;
      offset += field.bytes();
      value += field.count;
      if (!field.isPadding()) stored += field.bytes();
      for (int axis = 0; axis < 3; ++axis) {
        if (field.name != names[axis]) continue;
        if (layout_.coordinateField[axis] >= 0) Fail(fieldsLine_, std::string("two fields named '") + names[axis] + "'");
        layout_.coordinateField[axis] = static_cast<int>(i);
      }
    }
    layout_.pointBytes = offset;
    layout_.storedPointBytes = stored;
    layout_.valuesPerLine = value;
    if (layout_.coordinateField[0] < 0 || layout_.coordinateField[1] < 0) Fail(fieldsLine_, "the fields have no x or no y");
    // PCL's rules: without WIDTH and HEIGHT the cloud is POINTS wide;
    // without HEIGHT it is one row high.
    if (layout_.widthLine < 0) {
      if (layout_.heightLine >= 0) Fail("HEIGHT without WIDTH");
      if (layout_.pointsLine < 0) Fail("the header has neither WIDTH nor POINTS");
      layout_.width = layout_.points;
    }
    if (layout_.heightLine < 0) layout_.height = 1;
    const bool overflow = layout_.height != 0 && layout_.width > UINT64_MAX / layout_.height;
    const std::uint64_t product = overflow ? 0 : layout_.width * layout_.height;
    if (layout_.pointsLine < 0 && !overflow) layout_.points = product;
    if (overflow || product != layout_.points) {
      Fail("WIDTH (" + std::to_string(layout_.width) + ") x HEIGHT (" + std::to_string(layout_.height) +
           ") is not POINTS (" + std::to_string(layout_.points) + ")");
    }
  }

  /// A set of the keywords seen, to refuse repeated lines.
  struct Seen {
    std::vector<std::string> keywords;
    bool insert(const std::string& keyword) {
      if (std::find(keywords.begin(), keywords.end(), keyword) != keywords.end()) return false;
      keywords.push_back(keyword);
      return true;
    }
  };

  InputBuffer& input_;
  const std::string& path_;
  PcdLayout layout_;
  Seen seen_;
  std::int64_t lineNumber_ = 0;
  std::int64_t fieldsLine_ = 0;  ///< Line of FIELDS, for errors found at the end.
  std::int64_t sizeLine_ = 0;  ///< Line of SIZE (0: none yet).
  std::int64_t typeLine_ = 0;  ///< Line of TYPE (0: none yet).
};

}  // namespace

PcdLayout ReadPcdHeader(InputBuffer& input, const std::string& path) { return HeaderParser(input, path).Parse(); }

double PcdValue(const char* p, char type, std::size_t size) {
  switch (size) {
    case 1:
      return type == 'I' ? static_cast<double>(static_cast<std::int8_t>(*p)) : static_cast<unsigned char>(*p);
    case 2:
      return type == 'I' ? LoadValue<std::int16_t>(p, false) : LoadValue<std::uint16_t>(p, false);
    case 4:
      if (type == 'F') return LoadValue<float>(p, false);
      return type == 'I' ? LoadValue<std::int32_t>(p, false) : LoadValue<std::uint32_t>(p, false);
    default:
      if (type == 'F') return LoadValue<double>(p, false);
      return type == 'I' ? static_cast<double>(LoadValue<std::int64_t>(p, false))
                         : static_cast<double>(LoadValue<std::uint64_t>(p, false));
  }
}

std::string PcdPatchableCountLine(const std::string& keyword, std::uint64_t count) {
  std::string digits = std::to_string(count);
  if (digits.size() > kPatchableDigits) throw std::length_error("PcdPatchableCountLine: count too large");
  // "\n#" plus one space per unused digit keeps the length fixed.
  return keyword + " " + digits + "\n#" + std::string(kPatchableDigits - digits.size(), ' ');
}

bool IsPcdPaddingLine(const std::string& line) {
  const std::size_t end = line.find_last_not_of("\r\n");
  return end != std::string::npos && line[0] == '#' && line.find_first_not_of(' ', 1) > end;
}

}  // namespace invmap::io
