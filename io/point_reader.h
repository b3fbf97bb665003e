// Streaming input of query points (docs/formats.md, point files): text
// (.xyz, .txt, .csv), PLY, npy, LAS and PCD files are read sequentially in
// chunks, so inputs larger than memory work and memory stays bounded by the
// chunk size. Each chunk also carries the points' records verbatim so that
// `trim` can write kept points back unchanged with all their attributes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "io/input_error.h"
#include "io/las_format.h"
#include "io/pcd_format.h"
#include "io/ply.h"

namespace invmap::io {

/// File format family of a point file, from its extension.
enum class PointFormat : std::uint8_t {
  Text,  ///< .xyz, .txt, .csv
  Ply,   ///< .ply
  Npy,   ///< .npy
  Las,   ///< .las
  Pcd,   ///< .pcd
};

/// True, with the format family in `*format`, when the extension of `path`
/// (case-insensitive) is one of .xyz .txt .csv .ply .npy .las .pcd.
bool IsPointFileName(const std::string& path, PointFormat* format);

/// Format family of `path` from its extension (case-insensitive). Throws
/// InputError of kind `kind` naming the file when the extension is none of
/// .xyz .txt .csv .ply .npy .las .pcd (.laz with the reason it is refused).
PointFormat PointFormatOf(const std::string& path, InputError::Kind kind = InputError::Kind::Input);

/// A chunk size for ReadChunk: large enough that per-chunk costs vanish,
/// small enough that a chunk with its raw records and results stays in the
/// low hundreds of MB whatever the input size.
inline constexpr std::size_t kDefaultChunkPoints = std::size_t{1} << 21;

/// Most record bytes a LAS or PCD reader puts in one chunk: wide records
/// (extra bytes, feature descriptors) make chunks of fewer points, so that
/// a chunk's memory does not grow with the record size.
inline constexpr std::size_t kMaxChunkRecordBytes = std::size_t{128} << 20;

/// A run of consecutive points of the input.
struct PointChunk {
  /// Coordinates, point-major: count * dim values (dim of the reader).
  std::vector<double> xyz;
  /// Points in this chunk.
  std::size_t count = 0;
  /// 0-based input index of the first point.
  std::int64_t firstIndex = 0;
  /// Optional (PointReadOptions::keepRaw): the points' records verbatim,
  /// concatenated: text, each line with its terminator ("\n" added to a
  /// last line without one); PLY, each record (binary bytes, or the ascii
  /// line); npy, each row's bytes; LAS, each point data record; PCD, each
  /// ascii line or binary record (binary_compressed: the point's values of
  /// every field but the "_" padding, in field order).
  std::string raw;
  /// Optional (with raw): count + 1 offsets; point i's record is
  /// raw[rawOffsets[i], rawOffsets[i + 1]).
  std::vector<std::size_t> rawOffsets;
};

/// What is needed besides the records to write a file of the input's
/// format: the text header line, the PLY header, the npy dtype.
struct PointFileLayout {
  PointFormat format = PointFormat::Text;
  /// Text: the header line verbatim with its terminator; empty when the
  /// file has none.
  std::string textHeader;
  /// PLY: the input's header.
  PlyHeader plyHeader;
  /// PLY: index of the "vertex" element in plyHeader.elements.
  std::size_t plyVertexElement = 0;
  /// npy: the dtype descriptor, e.g. "<f8".
  std::string npyDescr;
  /// npy: the number of columns (shape[1]), 2 or 3.
  int npyColumns = 0;
  /// LAS: the header's facts and where the records lie.
  LasLayout las;
  /// PCD: the header, its fields and encoding.
  PcdLayout pcd;
};

/// Options of OpenPointReader.
struct PointReadOptions {
  /// 0: detect the dimension (see OpenPointReader); 2 or 3: use the first
  /// 2 or 3 coordinates (columns, or x y z properties) whatever follows.
  int forcedDim = 0;
  /// Fill PointChunk::raw and rawOffsets (needed by TrimWriter only; costs
  /// a copy of the records).
  bool keepRaw = true;
};

/// A sequential reader of the points of one file. Not thread-safe.
class PointReader {
 public:
  virtual ~PointReader() = default;

  /// Dimension of the points, 2 or 3.
  int dim() const { return dim_; }
  /// Number of points the file declares (PLY, npy), -1 when unknown (text).
  std::int64_t totalCountHint() const { return totalCountHint_; }
  /// Name of the file, as in messages.
  const std::string& path() const { return path_; }
  /// The input's format details, for TrimWriter.
  const PointFileLayout& layout() const { return layout_; }

  /// Reads up to maxPoints (> 0) next points into `chunk`, replacing its
  /// contents (its buffers' capacity is reused). Returns false, with
  /// chunk->count = 0, once all points have been read. Throws InputError
  /// (with the line for text files) for malformed or truncated data; the
  /// points of earlier chunks remain valid.
  bool ReadChunk(std::size_t maxPoints, PointChunk* chunk);

 protected:
  /// Base of a reader of `path`; keepRaw: see PointReadOptions.
  PointReader(std::string path, bool keepRaw) : path_(std::move(path)), keepRaw_(keepRaw) {}

  /// Appends up to maxPoints points to chunk->xyz (and raw records when
  /// keepRaw_) and returns how many.
  virtual std::size_t ReadPoints(std::size_t maxPoints, PointChunk* chunk) = 0;

  std::string path_;                  ///< See path().
  bool keepRaw_;                      ///< See PointReadOptions::keepRaw.
  int dim_ = 3;                       ///< See dim().
  std::int64_t totalCountHint_ = -1;  ///< See totalCountHint().
  /// Bytes of one raw record when known (binary formats; a lower bound with
  /// PLY lists), else 0; sizes the raw buffer of a chunk up front.
  std::size_t recordBytesHint_ = 0;
  PointFileLayout layout_;  ///< See layout().

 private:
  std::int64_t nextIndex_ = 0;  ///< Input index of the next point.
};

/// Opens a point file, choosing the format by extension (case-insensitive):
///  - .xyz .txt .csv: one point per line, fields separated by white space
///    and/or single commas (two commas in a row make an empty field). The
///    first non-blank line is a header when its first field is not a
///    number; it and any further columns are kept for trim. Blank lines are
///    skipped. Dimension, unless forced: 3 when the first data line starts
///    with at least 3 numbers, 2 when with exactly 2 (so a 2D file with a
///    numeric attribute column needs forcedDim = 2). Every data line must
///    start with dim numbers ("nan", "inf" allowed: such points get status
///    invalid). A file without data lines is an error.
///  - .ply: element "vertex" with scalar properties x, y and optionally z of
///    any numeric type; dimension 3 when z is present. The other vertex
///    properties pass through in the raw records; other elements are
///    skipped (and dropped by trim).
///  - .npy: float32 or float64 ('<f4' '<f8' '>f4' '>f8' '=f4' '=f8'),
///    C order, shape (N, 2) or (N, 3), format versions 1 to 3.
///  - .las: see OpenLasPointReader (io/las_reader.h); .laz is refused.
///  - .pcd: see OpenPcdPointReader (io/pcd_reader.h).
/// Throws InputError for missing, unreadable or malformed files, and for
/// headers that claim more data than the file holds (checked before
/// anything is reserved); std::invalid_argument for a forcedDim other
/// than 0, 2 or 3.
std::unique_ptr<PointReader> OpenPointReader(const std::string& path, const PointReadOptions& options = {});

/// As above with options.forcedDim = forcedDim (0, 2 or 3).
std::unique_ptr<PointReader> OpenPointReader(const std::string& path, int forcedDim);

}  // namespace invmap::io
