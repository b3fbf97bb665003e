#include "io/las_trim.h"

#include <algorithm>
#include <cstring>
#include <vector>

#include "io/input_error.h"
#include "io/positional_file.h"

namespace invmap::io {
namespace {

/// Copies bytes [begin, end) of the input to `out`.
void CopyRange(const LasLayout& layout, std::uint64_t begin, std::uint64_t end, AtomicOutput* out) {
  const PositionalFile input(layout.path);
  std::vector<char> block(std::size_t{1} << 20);
  while (begin < end) {
    const auto n = static_cast<std::size_t>(std::min<std::uint64_t>(block.size(), end - begin));
    if (input.ReadAt(begin, block.data(), n) != n) {
      throw InputError(layout.path, 0, "the file became shorter while it was being read");
    }
    out->Write(block.data(), n);
    begin += n;
  }
}

/// Overwrites the little-endian value at `offset` of the output.
template <class T>
void Patch(AtomicOutput* out, std::size_t offset, T value) {
  char bytes[sizeof(T)];
  StoreLittleEndian(bytes, value);
  out->WriteAt(static_cast<std::int64_t>(offset), bytes, sizeof(T));
}

}  // namespace

LasTrimWriter::LasTrimWriter(const LasLayout& layout, AtomicOutput* out) : layout_(layout) {
  CopyRange(layout_, 0, layout_.pointDataOffset, out);
}

void LasTrimWriter::Tally(const char* records, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i, records += layout_.recordLength) {
    const int returnNumber = las::ReturnNumber(records, layout_.pointFormat);
    if (returnNumber >= 1) ++byReturn_[returnNumber - 1];
    for (int axis = 0; axis < 3; ++axis) {
      const auto value = LoadValue<std::int32_t>(records + 4 * axis, false);
      min_[axis] = kept_ == 0 ? value : std::min(min_[axis], value);
      max_[axis] = kept_ == 0 ? value : std::max(max_[axis], value);
    }
    ++kept_;
  }
}

void LasTrimWriter::Finish(AtomicOutput* out) {
  const std::uint64_t removedBytes = (layout_.pointCount - kept_) * layout_.recordLength;
  CopyRange(layout_, layout_.pointDataEnd(), layout_.fileSize, out);

  const bool legacy = layout_.legacyCounts && kept_ <= UINT32_MAX;
  Patch(out, las::kLegacyPointCount, static_cast<std::uint32_t>(legacy ? kept_ : 0));
  for (int r = 0; r < las::kLegacyReturns; ++r) {
    Patch(out, las::kLegacyByReturn + 4 * static_cast<std::size_t>(r),
          static_cast<std::uint32_t>(legacy ? byReturn_[r] : 0));
  }
  for (int axis = 0; axis < 3; ++axis) {
    // The coordinates of the extreme records, as the reader computes them
    // (a negative scale swaps the ends).
    double a = 0.0;
    double b = 0.0;
    if (kept_ > 0) {
      a = static_cast<double>(min_[axis]) * layout_.scale[axis] + layout_.offset[axis];
      b = static_cast<double>(max_[axis]) * layout_.scale[axis] + layout_.offset[axis];
    }
    Patch(out, las::kBounds + 16 * static_cast<std::size_t>(axis), std::max(a, b));
    Patch(out, las::kBounds + 16 * static_cast<std::size_t>(axis) + 8, std::min(a, b));
  }
  if (layout_.waveformStart != 0) Patch(out, las::kWaveformStart, layout_.waveformStart - removedBytes);
  if (layout_.versionMinor == 4) {
    // The first extended record moves with the bytes after the points; a
    // start that points elsewhere (allowed only when there is none) stays.
    if (layout_.evlrStart >= layout_.pointDataEnd()) Patch(out, las::kEvlrStart, layout_.evlrStart - removedBytes);
    Patch(out, las::kPointCount, kept_);
    for (int r = 0; r < las::kExtendedReturns; ++r) {
      Patch(out, las::kByReturn + 8 * static_cast<std::size_t>(r), byReturn_[r]);
    }
  }
}

}  // namespace invmap::io
