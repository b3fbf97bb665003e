#include "io/pcd_trim.h"

#include <lzf.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "io/input_error.h"

namespace invmap::io {
namespace {

/// Uncompressed bytes compressed at a time. LZF looks back 8 KiB at most,
/// so blocks this large lose nothing to their boundaries; the blocks'
/// outputs concatenated decompress as one.
constexpr std::size_t kCompressBlock = std::size_t{1} << 20;

/// The terminator of a header line ("\r\n" or "\n").
std::string Terminator(const std::string& line) {
  return line.size() >= 2 && line.compare(line.size() - 2, 2, "\r\n") == 0 ? "\r\n" : "\n";
}

/// Writes `value` little-endian at `offset` of `out`.
void PatchUint32(AtomicOutput* out, std::int64_t offset, std::uint32_t value) {
  char bytes[4];
  StoreLittleEndian(bytes, value);
  out->WriteAt(offset, bytes, 4);
}

}  // namespace

PcdTrimWriter::PcdTrimWriter(const PcdLayout& layout, AtomicOutput* out) : layout_(layout) {
  if (layout_.encoding != PcdEncoding::BinaryCompressed) {
    WriteHeader(0, true, out);
    return;
  }
  columns_ = std::make_unique<AtomicOutput>(out->path());
  std::uint64_t start = 0;
  for (const PcdField& field : layout_.fields) {
    if (field.isPadding()) continue;
    columnStart_.push_back(start);
    fieldBytes_.push_back(field.bytes());
    start += layout_.points * field.bytes();
  }
}

PcdTrimWriter::~PcdTrimWriter() = default;

void PcdTrimWriter::WriteHeader(std::uint64_t count, bool patchable, AtomicOutput* out) {
  for (std::size_t i = 0; i < layout_.headerLines.size(); ++i) {
    const std::string& line = layout_.headerLines[i];
    // The padding of a count written by an earlier trim: the count written
    // here brings its own.
    if (IsPcdPaddingLine(line)) continue;
    const int index = static_cast<int>(i);
    if (index == layout_.widthLine || index == layout_.pointsLine) {
      const std::string keyword = index == layout_.widthLine ? "WIDTH" : "POINTS";
      if (patchable) (index == layout_.widthLine ? widthAt_ : pointsAt_) = out->size();
      out->Write((patchable ? PcdPatchableCountLine(keyword, count) : keyword + " " + std::to_string(count)) +
                 Terminator(line));
    } else if (index == layout_.heightLine) {
      out->Write("HEIGHT 1" + Terminator(line));
    } else {
      out->Write(line);
    }
  }
}

void PcdTrimWriter::Write(const char* records, std::size_t bytes, std::size_t count, AtomicOutput* out) {
  if (!columns_) {
    out->Write(records, bytes);
    kept_ += count;
    return;
  }
  // Each stored field's values of these points go to the end of its column.
  std::size_t fieldOffset = 0;
  for (std::size_t f = 0; f < fieldBytes_.size(); ++f) {
    const std::size_t size = fieldBytes_[f];
    scratch_.resize(count * size);
    for (std::size_t i = 0; i < count; ++i) {
      std::memcpy(scratch_.data() + i * size, records + i * layout_.storedPointBytes + fieldOffset, size);
    }
    columns_->WriteAt(static_cast<std::int64_t>(columnStart_[f] + kept_ * size), scratch_.data(), scratch_.size());
    fieldOffset += size;
  }
  kept_ += count;
}

void PcdTrimWriter::Finish(AtomicOutput* out) {
  if (columns_) {
    WriteCompressed(out);
    columns_.reset();
    return;
  }
  if (widthAt_ >= 0) {
    const std::string line = PcdPatchableCountLine("WIDTH", kept_);
    out->WriteAt(widthAt_, line.data(), line.size());
  }
  if (pointsAt_ >= 0) {
    const std::string line = PcdPatchableCountLine("POINTS", kept_);
    out->WriteAt(pointsAt_, line.data(), line.size());
  }
}

void PcdTrimWriter::WriteCompressed(AtomicOutput* out) {
  WriteHeader(kept_, false, out);
  const std::int64_t sizesAt = out->size();
  out->Write(std::string(8, '\0'));
  // At most the input's uncompressed size, which fits (the reader checked).
  const std::uint64_t uncompressed = kept_ * layout_.storedPointBytes;
  std::vector<char> block;
  block.reserve(kCompressBlock);
  // LZF output is at most 104% of its input.
  std::vector<char> packed(kCompressBlock + kCompressBlock / 16 + 64);
  std::uint64_t compressed = 0;
  const auto flush = [&] {
    if (block.empty()) return;
    const unsigned int n = lzf_compress(block.data(), static_cast<unsigned int>(block.size()), packed.data(),
                                        static_cast<unsigned int>(packed.size()));
    if (n == 0) throw std::logic_error("PcdTrimWriter: lzf_compress found no room");
    out->Write(packed.data(), n);
    compressed += n;
    block.clear();
  };
  for (std::size_t f = 0; f < fieldBytes_.size(); ++f) {
    std::uint64_t at = columnStart_[f];
    std::uint64_t left = kept_ * fieldBytes_[f];
    while (left > 0) {
      const auto n = static_cast<std::size_t>(std::min<std::uint64_t>(left, kCompressBlock - block.size()));
      const std::size_t old = block.size();
      block.resize(old + n);
      columns_->ReadAt(static_cast<std::int64_t>(at), block.data() + old, n);
      at += n;
      left -= n;
      if (block.size() == kCompressBlock) flush();
    }
  }
  flush();
  if (compressed > UINT32_MAX || uncompressed > UINT32_MAX) {
    throw InputError(out->path(), 0, "the kept points do not fit binary_compressed's 4 GiB", InputError::Kind::Output);
  }
  PatchUint32(out, sizesAt, static_cast<std::uint32_t>(compressed));
  PatchUint32(out, sizesAt + 4, static_cast<std::uint32_t>(uncompressed));
}

}  // namespace invmap::io
