// The one exception type of io/: bad input, with the file and line it names.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace invmap::io {

/// Unreadable or invalid input (command-line exit code 3) or an unwritable
/// output (exit code 4). The message names the file and, for text formats,
/// the 1-based line: "points.xyz:12: expected 3 numbers, found 2".
class InputError : public std::runtime_error {
 public:
  enum class Kind { Input, Output };

  /// `line` is 0 when the format has no lines (binary) or none applies.
  InputError(const std::string& file, std::int64_t line, const std::string& what, Kind kind = Kind::Input)
      : std::runtime_error(Format(file, line, what)), file_(file), line_(line), kind_(kind) {}

  const std::string& file() const { return file_; }
  std::int64_t line() const { return line_; }
  Kind kind() const { return kind_; }

 private:
  static std::string Format(const std::string& file, std::int64_t line, const std::string& what) {
    return Printable(line > 0 ? file + ":" + std::to_string(line) + ": " + what : file + ": " + what);
  }

  /// `text` with control bytes and bytes that are not UTF-8 written as \xNN:
  /// messages quote the file's own bytes, a NUL would end what() where it
  /// stands, and a caller decoding the message as UTF-8 (Python's text mode)
  /// must not fail on a binary file's bytes. Valid UTF-8 (file names) is kept.
  static std::string Printable(const std::string& text) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size();) {
      const auto byte = static_cast<unsigned char>(text[i]);
      if (byte >= 0x80) {
        const std::size_t length = Utf8SequenceLength(text, i);
        if (length > 0) {
          out.append(text, i, length);
          i += length;
          continue;
        }
      }
      if (byte >= 0x20 && byte < 0x7f) {
        out += text[i];
      } else {
        AppendHex(byte, &out);
      }
      ++i;
    }
    return out;
  }

  /// The length of the well-formed UTF-8 sequence starting at text[i] (a lead
  /// byte at or above 0x80), or 0 where it is not one: RFC 3629's table, so
  /// overlong forms and surrogates count as not UTF-8.
  static std::size_t Utf8SequenceLength(const std::string& text, std::size_t i) {
    const auto at = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
    const unsigned char lead = at(i);
    std::size_t length = 0;
    unsigned char secondLo = 0x80, secondHi = 0xbf;
    if (lead >= 0xc2 && lead <= 0xdf) {
      length = 2;
    } else if (lead >= 0xe0 && lead <= 0xef) {
      length = 3;
      if (lead == 0xe0) secondLo = 0xa0;
      if (lead == 0xed) secondHi = 0x9f;
    } else if (lead >= 0xf0 && lead <= 0xf4) {
      length = 4;
      if (lead == 0xf0) secondLo = 0x90;
      if (lead == 0xf4) secondHi = 0x8f;
    } else {
      return 0;
    }
    if (i + length > text.size() || at(i + 1) < secondLo || at(i + 1) > secondHi) return 0;
    for (std::size_t k = 2; k < length; ++k) {
      if (at(i + k) < 0x80 || at(i + k) > 0xbf) return 0;
    }
    return length;
  }

  static void AppendHex(unsigned char byte, std::string* out) {
    static constexpr char kHex[] = "0123456789abcdef";
    *out += "\\x";
    *out += kHex[byte >> 4];
    *out += kHex[byte & 15];
  }

  std::string file_;
  std::int64_t line_;
  Kind kind_;
};

}  // namespace invmap::io
