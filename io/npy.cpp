#include "io/npy.h"

#include <cstring>
#include <string_view>

#include "io/input_error.h"

namespace invmap::io {
namespace {

/// Longest header dictionary accepted; numpy writes well under 1 KiB.
constexpr std::uint32_t kMaxDictBytes = 1u << 20;

/// Recursive-descent reader of the Python literal dictionary of an npy
/// header: string keys; values that are strings, True/False or tuples of
/// integers.
class DictParser {
 public:
  /// Parses `text` (the dictionary) of `file` (named in errors).
  DictParser(std::string_view text, const std::string& file) : text_(text), file_(file) {}

  /// The header fields; throws InputError for a malformed dictionary.
  NpyHeader Parse() {
    NpyHeader header;
    bool haveDescr = false;
    bool haveOrder = false;
    bool haveShape = false;
    Expect('{');
    for (;;) {
      SkipSpace();
      if (Peek() == '}') break;
      const std::string key = String();
      Expect(':');
      SkipSpace();
      if (key == "descr") {
        if (Peek() != '\'' && Peek() != '"') Fail("structured dtypes are not supported (descr is not a string)");
        header.descr = String();
        haveDescr = true;
      } else if (key == "fortran_order") {
        header.fortranOrder = Bool();
        haveOrder = true;
      } else if (key == "shape") {
        header.shape = Tuple();
        haveShape = true;
      } else {
        Fail("unexpected key '" + key + "' in the header");
      }
      SkipSpace();
      if (Peek() == ',') ++pos_;
    }
    if (!haveDescr || !haveOrder || !haveShape) Fail("the header lacks descr, fortran_order or shape");
    return header;
  }

 private:
  /// Throws InputError with `what`.
  [[noreturn]] void Fail(const std::string& what) const { throw InputError(file_, 0, what); }
  /// The next character, '\0' at the end.
  char Peek() const { return pos_ < text_.size() ? text_[pos_] : '\0'; }
  /// Skips white space.
  void SkipSpace() {
    while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\t' || text_[pos_] == '\n')) ++pos_;
  }
  /// Consumes `c` after white space, else throws.
  void Expect(char c) {
    SkipSpace();
    if (Peek() != c) Fail(std::string("malformed header: expected '") + c + "'");
    ++pos_;
  }
  /// A quoted string (no escapes, which npy headers do not use).
  std::string String() {
    SkipSpace();
    const char quote = Peek();
    if (quote != '\'' && quote != '"') Fail("malformed header: expected a string");
    const std::size_t end = text_.find(quote, pos_ + 1);
    if (end == std::string_view::npos) Fail("malformed header: unterminated string");
    std::string value(text_.substr(pos_ + 1, end - pos_ - 1));
    pos_ = end + 1;
    return value;
  }
  /// True or False.
  bool Bool() {
    if (text_.substr(pos_, 4) == "True") {
      pos_ += 4;
      return true;
    }
    if (text_.substr(pos_, 5) == "False") {
      pos_ += 5;
      return false;
    }
    Fail("malformed header: expected True or False");
  }
  /// A tuple of non-negative integers, e.g. (10, 3) or (10,).
  std::vector<std::int64_t> Tuple() {
    std::vector<std::int64_t> values;
    Expect('(');
    for (;;) {
      SkipSpace();
      if (Peek() == ')') break;
      const std::size_t start = pos_;
      while (pos_ < text_.size() && text_[pos_] >= '0' && text_[pos_] <= '9') ++pos_;
      std::int64_t value = 0;
      if (!ParseInteger(text_.substr(start, pos_ - start), &value)) Fail("malformed header: bad shape");
      values.push_back(value);
      if (Peek() == 'L') ++pos_;  // Python 2 long suffix
      SkipSpace();
      if (Peek() == ',') {
        ++pos_;
      } else if (Peek() != ')') {
        Fail("malformed header: bad shape");
      }
    }
    ++pos_;
    return values;
  }

  std::string_view text_;    ///< The dictionary text.
  const std::string& file_;  ///< File name for messages.
  std::size_t pos_ = 0;      ///< Next character to read.
};

}  // namespace

NpyHeader ReadNpyHeader(InputBuffer& input) {
  const std::string& file = input.name();
  if (input.size() == 0) throw InputError(file, 0, "empty file");
  if (!input.Fill(10) || std::memcmp(input.data(), "\x93NUMPY", 6) != 0) {
    throw InputError(file, 0, "not a npy file (no \\x93NUMPY magic string)");
  }
  const int major = static_cast<unsigned char>(input.data()[6]);
  std::size_t prefix = 10;
  std::uint32_t dictBytes = 0;
  if (major == 1) {
    dictBytes = LoadValue<std::uint16_t>(input.data() + 8, false);
  } else if (major == 2 || major == 3) {
    if (!input.Fill(12)) throw InputError(file, 0, "truncated npy header");
    dictBytes = LoadValue<std::uint32_t>(input.data() + 8, false);
    prefix = 12;
  } else {
    throw InputError(file, 0, "unsupported npy format version " + std::to_string(major));
  }
  if (dictBytes > kMaxDictBytes || !input.Fill(prefix + dictBytes)) {
    throw InputError(file, 0, "truncated or oversized npy header");
  }
  NpyHeader header = DictParser(std::string_view(input.data() + prefix, dictBytes), file).Parse();
  input.Consume(prefix + dictBytes);
  header.dataOffset = input.offset();
  return header;
}

std::string FixedNpyHeader(const std::string& descr, std::int64_t rows, int columns) {
  std::string dict = "{'descr': '" + descr + "', 'fortran_order': False, 'shape': (" + std::to_string(rows) + ", " +
                     std::to_string(columns) + "), }";
  const std::size_t dictBytes = kNpyFixedHeaderBytes - 10;
  dict.resize(dictBytes - 1, ' ');
  dict.push_back('\n');
  std::string header("\x93NUMPY\x01\x00", 8);
  header.push_back(static_cast<char>(dictBytes & 0xff));
  header.push_back(static_cast<char>(dictBytes >> 8));
  return header + dict;
}

}  // namespace invmap::io
