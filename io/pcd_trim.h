// The PCD part of `invmap trim`: the kept points in the input's encoding,
// every field passed through, WIDTH/HEIGHT/POINTS rewritten.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "io/file_io.h"
#include "io/pcd_format.h"

namespace invmap::io {

/// Writes a PCD file of the kept points of the PCD input `layout`
/// describes, in the input's encoding: its header lines verbatim but for
/// WIDTH (the kept count), HEIGHT (1: a trimmed cloud is no longer
/// organized) and POINTS, then the kept points: ascii lines and binary
/// records byte for byte; binary_compressed, the kept values of each field
/// as one column after another, LZF-compressed (the layout PCL writes),
/// so the values are those of the input, bit for bit.
class PcdTrimWriter {
 public:
  /// Starts the output: ascii and binary write the header now, with counts
  /// patched at the end; binary_compressed keeps the kept columns in a
  /// scratch file beside `out` (deleted at the end) until the count is known.
  PcdTrimWriter(const PcdLayout& layout, AtomicOutput* out);
  ~PcdTrimWriter();

  /// Appends `count` consecutive kept records (`bytes` bytes at `records`,
  /// as the point reader gives them).
  void Write(const char* records, std::size_t bytes, std::size_t count, AtomicOutput* out);

  /// Writes or patches the counts (and binary_compressed data).
  void Finish(AtomicOutput* out);

 private:
  /// Writes the header lines with counts `count`; with `patchable`, each
  /// rewritten count line takes the same bytes whatever the final count and
  /// its offset is noted.
  void WriteHeader(std::uint64_t count, bool patchable, AtomicOutput* out);
  /// Binary_compressed: compresses the kept columns from the scratch file
  /// into `out`, after a header.
  void WriteCompressed(AtomicOutput* out);

  PcdLayout layout_;
  std::uint64_t kept_ = 0;
  /// Ascii and binary: output offsets of the WIDTH and POINTS lines to patch
  /// (-1: absent).
  std::int64_t widthAt_ = -1;
  std::int64_t pointsAt_ = -1;
  /// Binary_compressed: the kept values, field by field, each field's column
  /// at a fixed place (room for every input point), never committed.
  std::unique_ptr<AtomicOutput> columns_;
  std::vector<std::uint64_t> columnStart_;  ///< Offset of each stored field's column in columns_.
  std::vector<std::size_t> fieldBytes_;     ///< Bytes per point of each stored field.
  std::vector<char> scratch_;               ///< One column piece of a Write.
};

}  // namespace invmap::io
