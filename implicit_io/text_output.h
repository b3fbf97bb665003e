// Formatting numbers straight into an AtomicOutput's reserved space, for
// the text writers of the grid and zero-set files.
#pragma once

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>

namespace invmap::io {

/// Writes the shortest text that reads back as `value`; at most 24 characters.
inline char* PutDouble(char* p, double value) { return std::to_chars(p, p + 32, value).ptr; }
inline char* PutInteger(char* p, std::int64_t value) { return std::to_chars(p, p + 24, value).ptr; }
inline char* PutText(char* p, std::string_view text) {
  std::memcpy(p, text.data(), text.size());
  return p + text.size();
}

/// Room for one line of numbers: a few of them and separators.
constexpr std::size_t kLineRoom = 256;

}  // namespace invmap::io
