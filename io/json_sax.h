// What the SAX readers of io/ (geometry JSON, implicit function lists and
// CSG trees) share around nlohmann's SAX parser: iterators that tell the
// handler how far the lexer has read (SAX events carry no position, so this
// is how a handler learns the line of each value), over a text in memory or
// streamed from a file, and the wording of a parse error.
#pragma once

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <string>

#include "io/file_io.h"

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

/// A file read by nlohmann's SAX parser a character at a time, through an
/// InputBuffer, so that no more than a block of it is in memory whatever its
/// size (and an endless input fails at its first bad character). It keeps
/// what messages need: the line of any position since the last refill, and
/// the last bytes before the reading position.
class JsonTextStream {
 public:
  /// Reads `in` (not owned; it outlives the stream) from its current offset.
  explicit JsonTextStream(InputBuffer* in) : in_(in), pos_(in->data()), end_(in->data()) { Refill(); }

  JsonTextStream(const JsonTextStream&) = delete;
  JsonTextStream& operator=(const JsonTextStream&) = delete;

  /// Input iterator for nlohmann::json::sax_parse(begin(), end(), handler):
  /// every copy reads the one stream; the end copy compares equal once the
  /// input is exhausted.
  class Iterator {
   public:
    using iterator_category = std::input_iterator_tag;
    using value_type = char;
    using difference_type = std::ptrdiff_t;
    using pointer = const char*;
    using reference = const char&;

    explicit Iterator(JsonTextStream* stream) : stream_(stream) {}
    reference operator*() const { return *stream_->pos_; }
    Iterator& operator++() {
      if (++stream_->pos_ == stream_->end_) stream_->Refill();
      return *this;
    }
    Iterator operator++(int) {
      Iterator before = *this;
      ++*this;
      return before;
    }
    bool operator==(const Iterator& other) const { return AtEnd() == other.AtEnd(); }
    bool operator!=(const Iterator& other) const { return !(*this == other); }

   private:
    bool AtEnd() const { return stream_ == nullptr || stream_->pos_ == stream_->end_; }
    JsonTextStream* stream_;  ///< Null for the end iterator.
  };

  Iterator begin() { return Iterator(this); }
  Iterator end() { return Iterator(nullptr); }

  /// Bytes the parser has read: the offset of the next one in the input.
  std::int64_t Offset() const { return in_->offset() + (pos_ - in_->data()); }

  /// 1-based line of the last byte before `offset` (an offset at most a
  /// few bytes behind Offset(), as a SAX event's or an error's, or
  /// Offset() + 1 for the line after everything read). The byte at
  /// offset - 1 itself is left out: the lexer reads a number's next
  /// character too, which may be a line's end.
  std::int64_t LineBefore(std::int64_t offset) {
    const std::int64_t windowStart = in_->offset();
    const std::int64_t target = std::max(windowStart, std::min(offset, Offset() + 1) - 1);
    const auto at = [&](std::int64_t byte) { return in_->data() + (byte - windowStart); };
    if (target >= countedTo_) {
      newlines_ += std::count(at(countedTo_), at(target), '\n');
    } else {
      newlines_ -= std::count(at(target), at(countedTo_), '\n');
    }
    countedTo_ = target;
    return 1 + newlines_;
  }

  /// True when the buffered bytes before the reading position are all
  /// JSON white space: for a parser that stopped before any value, the
  /// input held nothing else (any other byte stops the lexer within a few
  /// more, which the window keeps).
  bool OnlyBlankRead() const {
    for (const char* p = in_->data(); p < pos_; ++p) {
      if (*p != ' ' && *p != '\t' && *p != '\r' && *p != '\n') return false;
    }
    return true;
  }

  /// The line of the parser's position (see LineBefore).
  std::int64_t Line() { return LineBefore(Offset()); }

  /// The bytes still buffered around the reading position (at least the
  /// last kKeptBytes before it, when the input had them), for messages
  /// that quote a bad token: window()[Offset() - windowOffset()] is the
  /// next byte.
  const char* window() const { return in_->data(); }
  std::size_t windowSize() const { return in_->available(); }
  std::int64_t windowOffset() const { return in_->offset(); }

 private:
  /// Bytes kept before the reading position when the buffer moves on.
  static constexpr std::size_t kKeptBytes = 64;

  /// Moves the window on once its bytes are read; at the end of the input,
  /// pos_ == end_.
  void Refill() {
    const std::size_t read = in_->available() == 0 ? 0 : static_cast<std::size_t>(pos_ - in_->data());
    const std::size_t kept = std::min(read, kKeptBytes);
    LineBefore(Offset());  // lines are counted in the window only
    in_->Consume(read - kept);
    in_->Fill(kept + 1);
    pos_ = in_->data() + std::min(kept, in_->available());
    end_ = in_->data() + in_->available();
  }

  InputBuffer* in_;
  const char* pos_;              ///< The next byte to read.
  const char* end_;              ///< The end of the buffered bytes.
  std::int64_t countedTo_ = 0;   ///< Newlines before this offset are counted...
  std::int64_t newlines_ = 0;    ///< ...and this is how many.
};

/// The message of nlohmann's parse error `what` ("[json.exception.parse_error.101]
/// parse error at line 3, column 7: syntax error ...") without its id and
/// position (the caller names file and line), plus a hint when the bad token
/// at byte `position` of `text` is NaN or infinity. The lexer stops at the
/// first bad character ("N" of NaN, "a" of nan read as a broken null), so the
/// word around it is read from the text. A NUL byte, which the lexer takes
/// for the end of the input, is named as such.
inline std::string DescribeJsonParseError(const char* text, std::size_t size, std::size_t position, std::string what) {
  // nlohmann's lexer takes a NUL byte for the end of the input.
  if (position >= 1 && position <= size && text[position - 1] == '\0') {
    return "invalid JSON: a NUL byte (binary data, not a JSON text)";
  }
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
