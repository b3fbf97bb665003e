// Output of `invmap trim` (docs/formats.md section 6): the input points that pass
// a filter, written unchanged with all their attributes, in input order and
// in the input's own format.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "io/file_io.h"
#include "io/point_reader.h"

namespace invmap::io {

class LasTrimWriter;
class PcdTrimWriter;

/// Writes kept points of a PointReader's input to one file. The output is
/// the input's format (PointFileLayout::format) whatever it is called, and
/// its extension must name the same family (text .xyz/.txt/.csv, .ply,
/// .npy, .las, .pcd):
///  - text: the input's header line, if any, then the kept lines verbatim
///    (blank lines of the input are not points and are dropped);
///  - PLY: the input's header lines (format, comments, obj_info) and its
///    vertex element with all properties, the count patched at Finish
///    (PlyPatchableCount); other elements such as
///    faces are dropped, since their vertex indices would no longer hold;
///    then the kept records byte for byte (ascii: line for line);
///  - npy: a header with the input's dtype and shape (kept, columns), then
///    the kept rows byte for byte;
///  - LAS: see LasTrimWriter (io/las_trim.h);
///  - PCD: see PcdTrimWriter (io/pcd_trim.h).
/// The file appears under its name only after Finish; until then, or after
/// a failure, the output path is untouched. Not thread-safe.
class TrimWriter {
 public:
  /// Creates the temporary output for `path`. `layout` is the reader's
  /// layout(). Throws InputError of kind Output when the extension names
  /// another format family or the file cannot be created.
  TrimWriter(const std::string& path, const PointFileLayout& layout);
  ~TrimWriter();

  /// Appends the points i of `chunk` with keep[i] != 0 (keep has
  /// chunk.count entries). The chunk must come from a reader opened with
  /// keepRaw (else std::invalid_argument).
  void WriteChunk(const PointChunk& chunk, const unsigned char* keep);

  /// Patches the header count and renames the file onto the output path.
  void Finish();

  /// Points written so far.
  std::int64_t written() const { return written_; }

 private:
  AtomicOutput out_;               ///< The output, renamed into place by Finish.
  PointFormat format_;             ///< The input's format, which the output keeps.
  std::string npyDescr_;           ///< npy: the input's dtype.
  int npyColumns_ = 0;             ///< npy: the input's columns.
  std::int64_t countOffset_ = -1;  ///< PLY: offset of the vertex count digits.
  std::unique_ptr<LasTrimWriter> las_;  ///< LAS: the header's counts, bounds and offsets.
  std::unique_ptr<PcdTrimWriter> pcd_;  ///< PCD: the header's counts, the encoding.
  std::int64_t written_ = 0;
  bool finished_ = false;  ///< Set by a successful Finish.
};

}  // namespace invmap::io
