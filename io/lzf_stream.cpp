#include "io/lzf_stream.h"

#include <algorithm>
#include <cstring>

#include "io/input_error.h"

namespace invmap::io {

LzfStream::LzfStream(std::shared_ptr<const PositionalFile> file, std::uint64_t begin, std::uint64_t compressedSize,
                     std::uint64_t outputSize)
    : file_(std::move(file)),
      begin_(begin),
      end_(begin + compressedSize),
      outputSize_(outputSize),
      bufferStart_(begin),
      window_(kWindow) {}

void LzfStream::Fail(const std::string& what) const {
  throw InputError(file_->path(), 0,
                   "binary_compressed data, compressed byte " + std::to_string(position() - begin_) + " of " +
                       std::to_string(end_ - begin_) + ": " + what);
}

void LzfStream::Refill() {
  bufferStart_ = position();
  const auto n = static_cast<std::size_t>(std::min<std::uint64_t>(kInputBlock, end_ - bufferStart_));
  input_.resize(n);
  inputAt_ = 0;
  if (file_->ReadAt(bufferStart_, input_.data(), n) != n) Fail("the file ends inside the compressed data");
}

unsigned char LzfStream::NextByte() {
  if (inputAt_ == input_.size()) Refill();
  return static_cast<unsigned char>(input_[inputAt_++]);
}

void LzfStream::NextToken() {
  if (inputLeft() == 0) {
    Fail("the data ends after " + std::to_string(produced_) + " of its " + std::to_string(outputSize_) + " bytes");
  }
  const unsigned char control = NextByte();
  std::size_t length = 0;
  if (control < 32) {
    literalLeft_ = control + std::size_t{1};
    length = literalLeft_;
    if (literalLeft_ > inputLeft()) Fail("a literal run of " + std::to_string(literalLeft_) + " bytes is cut off");
  } else {
    std::size_t lengthCode = control >> 5;
    if (inputLeft() < (lengthCode == 7 ? 2u : 1u)) Fail("a back-reference is cut off");
    if (lengthCode == 7) lengthCode += NextByte();
    distance_ = ((static_cast<std::size_t>(control) & 0x1f) << 8) + NextByte() + 1;
    if (distance_ > produced_) {
      Fail("a back-reference reaches " + std::to_string(distance_) + " bytes back from byte " +
           std::to_string(produced_));
    }
    matchLeft_ = lengthCode + 2;
    length = matchLeft_;
  }
  if (length > outputSize_ - produced_) Fail("the data decompresses to more than " + std::to_string(outputSize_) + " bytes");
}

void LzfStream::Produce(char* out, std::size_t n) {
  constexpr std::size_t kMask = kWindow - 1;
  while (n > 0) {
    if (literalLeft_ == 0 && matchLeft_ == 0) NextToken();
    if (literalLeft_ > 0) {
      if (inputAt_ == input_.size()) Refill();
      const std::size_t k = std::min({n, literalLeft_, input_.size() - inputAt_});
      const char* source = input_.data() + inputAt_;
      for (std::size_t i = 0; i < k; ++i) window_[(produced_ + i) & kMask] = source[i];
      if (out != nullptr) {
        std::memcpy(out, source, k);
        out += k;
      }
      inputAt_ += k;
      literalLeft_ -= k;
      produced_ += k;
      n -= k;
    } else {
      // Byte by byte: a reference may overlap the bytes it produces.
      const std::size_t k = std::min(n, matchLeft_);
      for (std::size_t i = 0; i < k; ++i) {
        const char c = window_[(produced_ - distance_) & kMask];
        window_[produced_ & kMask] = c;
        ++produced_;
        if (out != nullptr) *out++ = c;
      }
      matchLeft_ -= k;
      n -= k;
    }
  }
}

void LzfStream::Skip(std::uint64_t n) {
  while (n > 0) {
    const auto step = static_cast<std::size_t>(std::min<std::uint64_t>(n, std::uint64_t{1} << 30));
    Produce(nullptr, step);
    n -= step;
  }
}

void LzfStream::ExpectEnd() const {
  // Every token produces bytes, so compressed bytes left over mean more
  // output than declared.
  if (inputLeft() > 0 || literalLeft_ > 0 || matchLeft_ > 0) {
    Fail("the data decompresses to more than " + std::to_string(outputSize_) + " bytes");
  }
  if (produced_ != outputSize_) {
    Fail("the data ends after " + std::to_string(produced_) + " of its " + std::to_string(outputSize_) + " bytes");
  }
}

}  // namespace invmap::io
