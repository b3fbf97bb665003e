#include "io/point_reader.h"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "io/file_io.h"
#include "io/input_error.h"
#include "io/las_reader.h"
#include "io/npy.h"
#include "io/pcd_reader.h"

namespace invmap::io {
namespace {

/// Most points ReadChunk reserves room for up front (24 MiB of 3D points).
constexpr std::size_t kMaxReservePoints = std::size_t{1} << 20;

/// Splits the next field off `rest`. Fields are separated by spaces or tabs
/// and/or one comma, so "1, 2,3 4" has four fields and "1,,3" an empty
/// second one. Returns false when no field is left.
bool NextField(std::string_view* rest, std::string_view* field) {
  std::size_t i = 0;
  while (i < rest->size() && ((*rest)[i] == ' ' || (*rest)[i] == '\t')) ++i;
  if (i == rest->size()) return false;
  const std::size_t start = i;
  while (i < rest->size() && (*rest)[i] != ' ' && (*rest)[i] != '\t' && (*rest)[i] != ',') ++i;
  *field = rest->substr(start, i - start);
  while (i < rest->size() && ((*rest)[i] == ' ' || (*rest)[i] == '\t')) ++i;
  if (i < rest->size() && (*rest)[i] == ',') ++i;
  rest->remove_prefix(i);
  return true;
}

/// True for an empty line or one of spaces and tabs only (skipped, not a point).
bool IsBlank(std::string_view line) { return line.find_first_not_of(" \t") == std::string_view::npos; }

/// Removes a UTF-8 byte order mark, which spreadsheet exports put first.
std::string_view StripBom(std::string_view line) { return line.substr(0, 3) == "\xEF\xBB\xBF" ? line.substr(3) : line; }

/// Number of fields at the start of `line` that are numbers, at most `most`.
int LeadingNumbers(std::string_view line, int most) {
  int numbers = 0;
  std::string_view field;
  double value = 0.0;
  while (numbers < most && NextField(&line, &field) && ParseDouble(field, &value)) ++numbers;
  return numbers;
}

/// Text point files: see OpenPointReader.
class TextPointReader : public PointReader {
 public:
  /// Opens `path`, reads the header line if any and the first data line to
  /// fix the dimension.
  TextPointReader(const std::string& path, const PointReadOptions& options)
      : PointReader(path, options.keepRaw), input_(path) {
    std::string_view line;
    std::string_view raw;
    if (!NextNonBlankLine(&line, &raw)) throw InputError(path_, 0, "empty file");
    line = StripBom(line);
    if (line.find('\r') != std::string_view::npos) {
      // Old Mac files end lines in a lone CR: the whole file reads as one line.
      throw InputError(path_, input_.lineNumber(),
                       "a carriage return inside the line: lines must end in \\n or \\r\\n, not in \\r alone");
    }
    if (LeadingNumbers(line, 1) == 0) {
      layout_.textHeader = std::string(raw);
      if (layout_.textHeader.back() != '\n') layout_.textHeader.push_back('\n');
      if (!NextNonBlankLine(&line, &raw)) throw InputError(path_, 0, "no data lines (only a header)");
    }
    const int numbers = LeadingNumbers(line, 3);
    if (options.forcedDim != 0) {
      dim_ = options.forcedDim;
    } else if (numbers >= 2) {
      dim_ = numbers;
    } else {
      throw InputError(path_, input_.lineNumber(), "expected at least 2 numbers at the start of the line");
    }
    // The line stays in the buffer only until the next read: keep a copy.
    pendingLine_ = std::string(line);
    pendingRaw_ = std::string(raw);
    pendingLineNumber_ = input_.lineNumber();
    hasPending_ = true;
  }

 private:
  /// Reads the next line that is not blank; false at the end of the file.
  bool NextNonBlankLine(std::string_view* line, std::string_view* raw) {
    while (input_.ReadLine(line, raw)) {
      if (!IsBlank(*line)) return true;
    }
    return false;
  }

  /// See PointReader::ReadPoints.
  std::size_t ReadPoints(std::size_t maxPoints, PointChunk* chunk) override {
    std::size_t count = 0;
    std::string_view line;
    std::string_view raw;
    while (count < maxPoints) {
      std::int64_t lineNumber = 0;
      if (hasPending_) {
        line = pendingLine_;
        raw = pendingRaw_;
        lineNumber = pendingLineNumber_;
        hasPending_ = false;
      } else {
        if (!NextNonBlankLine(&line, &raw)) break;
        lineNumber = input_.lineNumber();
      }
      const std::size_t at = chunk->xyz.size();
      chunk->xyz.resize(at + static_cast<std::size_t>(dim_));
      ParseCoordinates(line, lineNumber, chunk->xyz.data() + at);
      if (keepRaw_) {
        chunk->raw.append(raw.data(), raw.size());
        if (raw.back() != '\n') chunk->raw.push_back('\n');
        chunk->rawOffsets.push_back(chunk->raw.size());
      }
      ++count;
    }
    return count;
  }

  /// Parses the first dim_ fields of `line` (line `lineNumber` of the file)
  /// into out[0..dim_).
  void ParseCoordinates(std::string_view line, std::int64_t lineNumber, double* out) const {
    std::string_view rest = line;
    std::string_view field;
    for (int k = 0; k < dim_; ++k) {
      if (!NextField(&rest, &field)) {
        throw InputError(path_, lineNumber,
                         "expected " + std::to_string(dim_) + " numbers, found " + std::to_string(k));
      }
      if (!ParseDouble(field, out + k)) {
        throw InputError(path_, lineNumber,
                         "column " + std::to_string(k + 1) + ": '" + std::string(field) + "' is not a number");
      }
    }
  }

  InputBuffer input_;        ///< The file, read line by line.
  std::string pendingLine_;  ///< The first data line, read by the constructor.
  std::string pendingRaw_;   ///< Its raw bytes with terminator.
  std::int64_t pendingLineNumber_ = 0;
  bool hasPending_ = false;  ///< True until ReadPoints has taken the first data line.
};

/// PLY point files: the vertex element.
class PlyPointReader : public PointReader {
 public:
  /// Opens `path`, checks the vertex element and moves to its first record.
  PlyPointReader(const std::string& path, const PointReadOptions& options)
      : PointReader(path, options.keepRaw), reader_(path) {
    const PlyHeader& header = reader_.header();
    const int vertex = header.FindElement("vertex");
    if (vertex < 0) throw InputError(path_, 0, "no 'vertex' element");
    const PlyElement& element = header.elements[static_cast<std::size_t>(vertex)];
    const char* const names[3] = {"x", "y", "z"};
    for (int k = 0; k < 3; ++k) {
      property_[k] = element.FindProperty(names[k]);
      if (property_[k] >= 0 && element.properties[static_cast<std::size_t>(property_[k])].isList) {
        throw InputError(path_, 0, std::string("vertex property '") + names[k] + "' is a list, expected a number");
      }
    }
    if (property_[0] < 0 || property_[1] < 0) throw InputError(path_, 0, "the vertex element has no x or y property");
    dim_ = options.forcedDim != 0 ? options.forcedDim : (property_[2] >= 0 ? 3 : 2);
    if (dim_ == 3 && property_[2] < 0) throw InputError(path_, 0, "dimension 3 requested but the vertices have no z");
    totalCountHint_ = element.count;
    if (header.format != PlyFormat::Ascii) {
      for (const PlyProperty& property : element.properties) {
        recordBytesHint_ += static_cast<std::size_t>(PlyTypeSize(property.isList ? property.countType : property.type));
      }
    }
    layout_.format = PointFormat::Ply;
    layout_.plyHeader = header;
    layout_.plyVertexElement = static_cast<std::size_t>(vertex);
    reader_.SkipToElement(static_cast<std::size_t>(vertex));
  }

 private:
  /// See PointReader::ReadPoints.
  std::size_t ReadPoints(std::size_t maxPoints, PointChunk* chunk) override {
    std::size_t count = 0;
    while (count < maxPoints && reader_.element() == layout_.plyVertexElement &&
           reader_.ReadRecord(&record_, keepRaw_ ? &chunk->raw : nullptr)) {
      for (int k = 0; k < dim_; ++k) chunk->xyz.push_back(record_.Scalar(static_cast<std::size_t>(property_[k])));
      if (keepRaw_) chunk->rawOffsets.push_back(chunk->raw.size());
      ++count;
    }
    return count;
  }

  PlyReader reader_;                ///< The file, positioned in the vertex element.
  PlyRecord record_;                ///< Scratch record, reused for every point.
  int property_[3] = {-1, -1, -1};  ///< Indices of x, y, z in the vertex element (z: -1 if none).
};

/// npy point files.
class NpyPointReader : public PointReader {
 public:
  /// Opens `path` and checks its dtype, order and shape against the file size.
  NpyPointReader(const std::string& path, const PointReadOptions& options)
      : PointReader(path, options.keepRaw), input_(path) {
    const NpyHeader header = ReadNpyHeader(input_);
    const std::string& d = header.descr;
    if (d.size() != 3 || (d[0] != '<' && d[0] != '>' && d[0] != '=') || d[1] != 'f' || (d[2] != '4' && d[2] != '8')) {
      throw InputError(path_, 0,
                       "unsupported dtype '" + d + "' (expected float32 or float64: '<f4', '<f8', '>f4', '>f8')");
    }
    if (header.fortranOrder) {
      throw InputError(path_, 0,
                       "fortran_order is True (a column-major array): save a C-order array instead, e.g. "
                       "numpy.save(path, numpy.ascontiguousarray(points))");
    }
    if (header.shape.size() != 2 || (header.shape[1] != 2 && header.shape[1] != 3)) {
      std::string shape;
      for (std::int64_t n : header.shape) shape += (shape.empty() ? "" : ", ") + std::to_string(n);
      throw InputError(path_, 0, "shape (" + shape + ") is not (N, 2) or (N, 3)");
    }
    bigEndian_ = d[0] == '>' || (d[0] == '=' && kHostBigEndian);
    itemBytes_ = d[2] == '8' ? 8 : 4;
    columns_ = static_cast<int>(header.shape[1]);
    rows_ = header.shape[0];
    rowBytes_ = static_cast<std::size_t>(columns_) * itemBytes_;
    recordBytesHint_ = rowBytes_;
    const std::int64_t available = input_.remaining();
    if (available >= 0 && (rows_ > available / static_cast<std::int64_t>(rowBytes_) ||
                           rows_ * static_cast<std::int64_t>(rowBytes_) != available)) {
      throw InputError(path_, 0,
                       "shape (" + std::to_string(rows_) + ", " + std::to_string(columns_) + ") of " +
                           (itemBytes_ == 8 ? "float64" : "float32") + " does not match the " +
                           std::to_string(available) + " data bytes of the file");
    }
    if (options.forcedDim > columns_) {
      throw InputError(path_, 0, "dimension 3 requested but the array has 2 columns");
    }
    dim_ = options.forcedDim != 0 ? options.forcedDim : columns_;
    totalCountHint_ = rows_;
    layout_.format = PointFormat::Npy;
    layout_.npyDescr = d;
    layout_.npyColumns = columns_;
  }

 private:
  /// See PointReader::ReadPoints.
  std::size_t ReadPoints(std::size_t maxPoints, PointChunk* chunk) override {
    const std::size_t want = std::min(static_cast<std::size_t>(rows_ - done_), maxPoints);
    std::size_t count = 0;
    while (count < want) {
      if (!input_.Fill(rowBytes_)) {
        throw InputError(path_, 0, "the file ends at row " + std::to_string(done_) + " of " + std::to_string(rows_));
      }
      // Decode every whole row in the buffer at once.
      const std::size_t rows = std::min(want - count, input_.available() / rowBytes_);
      const char* p = input_.data();
      const std::size_t at = chunk->xyz.size();
      chunk->xyz.resize(at + rows * static_cast<std::size_t>(dim_));
      double* out = chunk->xyz.data() + at;
      for (std::size_t r = 0; r < rows; ++r, p += rowBytes_) {
        for (int k = 0; k < dim_; ++k) {
          *out++ = itemBytes_ == 8 ? LoadValue<double>(p + 8 * k, bigEndian_) : LoadValue<float>(p + 4 * k, bigEndian_);
        }
      }
      if (keepRaw_) {
        chunk->raw.append(input_.data(), rows * rowBytes_);
        for (std::size_t r = 0; r < rows; ++r) chunk->rawOffsets.push_back(chunk->rawOffsets.back() + rowBytes_);
      }
      input_.Consume(rows * rowBytes_);
      count += rows;
      done_ += static_cast<std::int64_t>(rows);
    }
    return count;
  }

  InputBuffer input_;          ///< The file, positioned at the next row.
  bool bigEndian_ = false;     ///< Byte order of the values.
  std::size_t itemBytes_ = 8;  ///< 4 (float32) or 8 (float64).
  int columns_ = 3;            ///< shape[1].
  std::int64_t rows_ = 0;      ///< shape[0].
  std::size_t rowBytes_ = 24;  ///< columns_ * itemBytes_.
  std::int64_t done_ = 0;      ///< Rows read so far.
};

}  // namespace

bool IsPointFileName(const std::string& path, PointFormat* format) {
  const std::string ext = LowerExtension(path);
  if (ext == ".xyz" || ext == ".txt" || ext == ".csv") {
    *format = PointFormat::Text;
  } else if (ext == ".ply") {
    *format = PointFormat::Ply;
  } else if (ext == ".npy") {
    *format = PointFormat::Npy;
  } else if (ext == ".las") {
    *format = PointFormat::Las;
  } else if (ext == ".pcd") {
    *format = PointFormat::Pcd;
  } else {
    return false;
  }
  return true;
}

PointFormat PointFormatOf(const std::string& path, InputError::Kind kind) {
  PointFormat format;
  if (IsPointFileName(path, &format)) return format;
  const std::string ext = LowerExtension(path);
  if (ext == ".laz") throw InputError(path, 0, LazRefusal(), kind);
  throw InputError(path, 0,
                   "unknown point file extension '" + ext + "' (expected .xyz, .txt, .csv, .ply, .npy, .las or .pcd)",
                   kind);
}

bool PointReader::ReadChunk(std::size_t maxPoints, PointChunk* chunk) {
  if (maxPoints == 0) throw std::invalid_argument("PointReader::ReadChunk: maxPoints must be positive");
  chunk->xyz.clear();
  chunk->raw.clear();
  chunk->rawOffsets.clear();
  if (keepRaw_) chunk->rawOffsets.push_back(0);
  if (totalCountHint_ > nextIndex_) {
    // Reserving avoids regrowing the buffers in the first chunk. The cap
    // keeps a count that was not checked against a file size (a pipe) from
    // reserving much.
    const std::size_t expected =
        std::min({static_cast<std::size_t>(totalCountHint_ - nextIndex_), maxPoints, kMaxReservePoints});
    chunk->xyz.reserve(expected * static_cast<std::size_t>(dim_));
    if (keepRaw_) {
      chunk->rawOffsets.reserve(expected + 1);
      chunk->raw.reserve(expected * recordBytesHint_);
    }
  }
  chunk->firstIndex = nextIndex_;
  chunk->count = ReadPoints(maxPoints, chunk);
  nextIndex_ += static_cast<std::int64_t>(chunk->count);
  return chunk->count > 0;
}

std::unique_ptr<PointReader> OpenPointReader(const std::string& path, const PointReadOptions& options) {
  if (options.forcedDim != 0 && options.forcedDim != 2 && options.forcedDim != 3) {
    throw std::invalid_argument("OpenPointReader: forcedDim must be 0, 2 or 3");
  }
  switch (PointFormatOf(path)) {
    case PointFormat::Text:
      return std::make_unique<TextPointReader>(path, options);
    case PointFormat::Ply:
      return std::make_unique<PlyPointReader>(path, options);
    case PointFormat::Npy:
      return std::make_unique<NpyPointReader>(path, options);
    case PointFormat::Las:
      return OpenLasPointReader(path, options);
    case PointFormat::Pcd:
      return OpenPcdPointReader(path, options);
  }
  return nullptr;
}

std::unique_ptr<PointReader> OpenPointReader(const std::string& path, int forcedDim) {
  PointReadOptions options;
  options.forcedDim = forcedDim;
  return OpenPointReader(path, options);
}

}  // namespace invmap::io
