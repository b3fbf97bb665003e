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

  /// `text` with control bytes written as \xNN: messages quote the file's
  /// own bytes, and a NUL would end what() where it stands.
  static std::string Printable(const std::string& text) {
    static constexpr char kHex[] = "0123456789abcdef";
    std::string out;
    out.reserve(text.size());
    for (const char c : text) {
      const auto byte = static_cast<unsigned char>(c);
      if (byte >= 0x20 && byte != 0x7f) {
        out += c;
      } else {
        out += "\\x";
        out += kHex[byte >> 4];
        out += kHex[byte & 15];
      }
    }
    return out;
  }

  std::string file_;
  std::int64_t line_;
  Kind kind_;
};

}  // namespace invmap::io
