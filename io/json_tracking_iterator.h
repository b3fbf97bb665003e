// A character iterator for nlohmann's lexer that publishes how far the lexer
// has read. nlohmann's SAX events carry no position, so this is how a SAX
// handler learns the line of each value (geometry JSON, implicit function
// lists and CSG trees).
#pragma once

#include <cstddef>
#include <iterator>

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

}  // namespace invmap::io
