// Streaming LZF decompression of a byte range of a file. liblzf (which
// trim uses to compress) decompresses a whole block into memory at once;
// a binary_compressed PCD file is one block of up to 4 GiB, laid out field
// by field, so the point reader instead runs one of these per field, each
// holding only LZF's 8 KiB window.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "io/positional_file.h"

namespace invmap::io {

/// The decompressed bytes of LZF data (liblzf's format: literal runs of 1
/// to 32 bytes, back-references of 3 to 264 bytes up to 8192 bytes back)
/// stored in bytes [begin, begin + compressedSize) of a file that should
/// decompress to exactly `outputSize` bytes. A copy is an independent
/// stream at the same position (the reader copies one at the start of each
/// field). Malformed data (a reference before the start, a run past the
/// end of the input, more or fewer bytes than outputSize) throws
/// InputError naming the file and the compressed byte.
class LzfStream {
 public:
  LzfStream(std::shared_ptr<const PositionalFile> file, std::uint64_t begin, std::uint64_t compressedSize,
            std::uint64_t outputSize);

  /// Writes the next n decompressed bytes to `out`.
  void Read(char* out, std::size_t n) { Produce(out, n); }
  /// Decompresses and drops the next n bytes.
  void Skip(std::uint64_t n);
  /// Decompressed bytes produced so far.
  std::uint64_t produced() const { return produced_; }
  /// Throws unless every compressed byte was used and exactly outputSize
  /// bytes came out (call after producing outputSize bytes).
  void ExpectEnd() const;

 private:
  /// The window: LZF references reach at most this far back.
  static constexpr std::size_t kWindow = 8192;
  /// Compressed bytes read from the file at a time.
  static constexpr std::size_t kInputBlock = 4096;

  /// Produces n bytes into out (nullptr: dropped).
  void Produce(char* out, std::size_t n);
  /// Reads the next token's control bytes and sets up its run.
  void NextToken();
  /// The next compressed byte.
  unsigned char NextByte();
  /// Reads the compressed bytes from position() on into input_.
  void Refill();
  /// File offset of the next compressed byte.
  std::uint64_t position() const { return bufferStart_ + inputAt_; }
  /// Compressed bytes not yet consumed.
  std::uint64_t inputLeft() const { return end_ - position(); }
  [[noreturn]] void Fail(const std::string& what) const;

  std::shared_ptr<const PositionalFile> file_;
  std::uint64_t begin_;        ///< File offset of the first compressed byte.
  std::uint64_t end_;          ///< File offset past the last compressed byte.
  std::uint64_t outputSize_;   ///< Bytes the data should decompress to.
  std::uint64_t bufferStart_;  ///< File offset of input_[0].
  std::vector<char> input_;    ///< Compressed bytes read ahead.
  std::size_t inputAt_ = 0;    ///< Next byte in input_.
  std::vector<char> window_;  ///< The last kWindow decompressed bytes, at produced % kWindow.
  std::uint64_t produced_ = 0;
  std::size_t literalLeft_ = 0;  ///< Bytes left of the current literal run.
  std::size_t matchLeft_ = 0;    ///< Bytes left of the current back-reference.
  std::size_t distance_ = 0;     ///< The back-reference's distance.
};

}  // namespace invmap::io
