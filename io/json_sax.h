// What the SAX readers of io/ (geometry JSON, implicit function lists and
// CSG trees) share around nlohmann's SAX parser: an iterator that tells the
// handler how far the lexer has read (SAX events carry no position, so this
// is how a handler learns the line of each value), and the wording of a
// parse error.
#pragma once

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <iterator>
#include <string>

namespace invmap::io {

/// Iterator over a text buffer: the begin copy advances a cursor shared with
/// the handler; the end copy is a fixed pointer.
class TrackingIterator {
 public:
  using iterator_category = std::input_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  /// The reading position: `*cursor` is the next character to read; the
  /// cursor outlives the parse.
  explicit TrackingIterator(const char** cursor) : cursor_(cursor), end_(nullptr) {}
  /// The end of the buffer.
  explicit TrackingIterator(const char* end) : cursor_(nullptr), end_(end) {}

  // Input-iterator operations, as nlohmann's iterator_input_adapter uses them.
  reference operator*() const { return **cursor_; }
  TrackingIterator& operator++() {
    ++*cursor_;
    return *this;
  }
  TrackingIterator operator++(int) {
    TrackingIterator before = *this;
    ++*cursor_;
    return before;
  }
  bool operator==(const TrackingIterator& other) const { return Position() == other.Position(); }
  bool operator!=(const TrackingIterator& other) const { return Position() != other.Position(); }

 private:
  const char* Position() const { return cursor_ ? *cursor_ : end_; }

  const char** cursor_;
  const char* end_;
};

/// The message of nlohmann's parse error `what` ("[json.exception.parse_error.101]
/// parse error at line 3, column 7: syntax error ...") without its id and
/// position (the caller names file and line), plus a hint when the bad token
/// at byte `position` of `text` is NaN or infinity. The lexer stops at the
/// first bad character ("N" of NaN, "a" of nan read as a broken null), so the
/// word around it is read from the text.
inline std::string DescribeJsonParseError(const char* text, std::size_t size, std::size_t position, std::string what) {
  if (const std::size_t bracket = what.find("] "); bracket != std::string::npos) what.erase(0, bracket + 2);
  if (what.rfind("parse error", 0) == 0) {
    if (const std::size_t colon = what.find(": "); colon != std::string::npos) what.erase(0, colon + 2);
  }
  const auto isAlpha = [&](std::size_t i) { return std::isalpha(static_cast<unsigned char>(text[i])) != 0; };
  std::size_t start = std::min(position, size);
  start = start > 0 ? start - 1 : 0;
  while (start > 0 && isAlpha(start - 1)) --start;
  std::string word;
  for (std::size_t i = start; i < size && word.size() < 9 && isAlpha(i); ++i) {
    word += static_cast<char>(std::tolower(static_cast<unsigned char>(text[i])));
  }
  if (word == "nan" || word == "inf" || word == "infinity") {
    what += " (JSON has no NaN or infinity: every number must be finite)";
  }
  return "invalid JSON: " + what;
}

}  // namespace invmap::io
