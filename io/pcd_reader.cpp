#include "io/pcd_reader.h"

#include <algorithm>
#include <cstdint>
#include <string_view>
#include <vector>

#include "io/file_io.h"
#include "io/input_error.h"
#include "io/lzf_stream.h"
#include "io/pcd_format.h"

namespace invmap::io {
namespace {

/// True for a line of spaces and tabs only.
bool IsBlank(std::string_view line) { return line.find_first_not_of(" \t") == std::string_view::npos; }

/// PCD point files: see OpenPcdPointReader.
class PcdPointReader : public PointReader {
 public:
  /// Opens `path`, parses the header and checks the data's size.
  PcdPointReader(const std::string& path, const PointReadOptions& options)
      : PointReader(path, options.keepRaw), input_(path) {
    layout_.format = PointFormat::Pcd;
    layout_.pcd = ReadPcdHeader(input_, path_);
    const PcdLayout& pcd = layout_.pcd;
    const bool hasZ = pcd.coordinateField[2] >= 0;
    dim_ = options.forcedDim != 0 ? options.forcedDim : (hasZ ? 3 : 2);
    if (dim_ == 3 && !hasZ) throw InputError(path_, 0, "dimension 3 requested but the fields have no z");
    totalCountHint_ = static_cast<std::int64_t>(std::min<std::uint64_t>(pcd.points, INT64_MAX));
    if (pcd.encoding == PcdEncoding::Binary) {
      const std::int64_t available = input_.remaining();
      if (available >= 0 && pcd.points > static_cast<std::uint64_t>(available) / pcd.pointBytes) {
        throw InputError(path_, 0,
                         "POINTS " + std::to_string(pcd.points) + " of " + std::to_string(pcd.pointBytes) +
                             " bytes do not fit in the " + std::to_string(available) + " bytes after the header");
      }
    } else if (pcd.encoding == PcdEncoding::BinaryCompressed) {
      OpenCompressedStreams();
    }
  }

 private:
  /// See PointReader::ReadPoints.
  std::size_t ReadPoints(std::size_t maxPoints, PointChunk* chunk) override {
    const PcdLayout& pcd = layout_.pcd;
    const std::size_t recordBytes =
        pcd.encoding == PcdEncoding::BinaryCompressed ? pcd.storedPointBytes : std::max<std::size_t>(pcd.pointBytes, 1);
    const std::size_t want = static_cast<std::size_t>(std::min<std::uint64_t>(
        {pcd.points - done_, maxPoints, std::max<std::size_t>(1, kMaxChunkRecordBytes / recordBytes)}));
    chunk->xyz.reserve(chunk->xyz.size() + want * static_cast<std::size_t>(dim_));
    std::size_t count = 0;
    switch (pcd.encoding) {
      case PcdEncoding::Ascii:
        count = ReadAscii(want, chunk);
        break;
      case PcdEncoding::Binary:
        count = ReadBinary(want, chunk);
        break;
      case PcdEncoding::BinaryCompressed:
        count = ReadCompressed(want, chunk);
        break;
    }
    done_ += count;
    return count;
  }

  /// Ascii: the next `want` non-blank lines.
  std::size_t ReadAscii(std::size_t want, PointChunk* chunk) {
    const PcdLayout& pcd = layout_.pcd;
    std::string_view line;
    std::string_view raw;
    std::size_t count = 0;
    // Lines may be long (padding, many values): the chunk also ends once
    // its records reach the byte cap.
    while (count < want && chunk->raw.size() < kMaxChunkRecordBytes) {
      if (!input_.ReadLine(&line, &raw)) {
        throw InputError(path_, input_.lineNumber(),
                         "the file ends after " + std::to_string(done_ + count) + " of its " +
                             std::to_string(pcd.points) + " points");
      }
      if (IsBlank(line)) continue;
      ParseAsciiPoint(line, chunk);
      if (keepRaw_) {
        chunk->raw.append(raw.data(), raw.size());
        if (raw.back() != '\n') chunk->raw.push_back('\n');
        chunk->rawOffsets.push_back(chunk->raw.size());
      }
      ++count;
    }
    if (done_ + count == pcd.points) {
      // A line past POINTS means the header's count is wrong.
      while (input_.ReadLine(&line)) {
        if (!IsBlank(line)) {
          throw InputError(path_, input_.lineNumber(),
                           "more points than the header's POINTS (" + std::to_string(pcd.points) + ")");
        }
      }
    }
    return count;
  }

  /// Appends the coordinates of one ascii point line to chunk->xyz after
  /// checking that it holds the header's number of values, all numbers.
  void ParseAsciiPoint(std::string_view line, PointChunk* chunk) const {
    const PcdLayout& pcd = layout_.pcd;
    const std::size_t at = chunk->xyz.size();
    chunk->xyz.resize(at + static_cast<std::size_t>(dim_));
    std::size_t values = 0;
    std::size_t field = 0;
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      const std::size_t start = i;
      while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
      if (i == start) break;
      const std::string_view token = line.substr(start, i - start);
      if (values == pcd.valuesPerLine) {
        throw InputError(path_, input_.lineNumber(),
                         "expected " + std::to_string(pcd.valuesPerLine) + " values (" +
                             std::to_string(pcd.fields.size()) + " fields), found more");
      }
      while (values >= pcd.fields[field].firstValue + pcd.fields[field].count) ++field;
      double value = 0.0;
      if (!ParseDouble(token, &value)) {
        throw InputError(path_, input_.lineNumber(),
                         "field '" + pcd.fields[field].name + "': '" + std::string(token) + "' is not a number");
      }
      for (int axis = 0; axis < dim_; ++axis) {
        const PcdField& coordinate = pcd.fields[static_cast<std::size_t>(pcd.coordinateField[axis])];
        if (values != coordinate.firstValue) continue;
        // The value the field holds, as in a binary file: a float field's
        // text ("0.1") is rounded to float, as PCL reads it.
        const bool isFloat = coordinate.type == 'F' && coordinate.size == 4;
        chunk->xyz[at + static_cast<std::size_t>(axis)] = isFloat ? static_cast<float>(value) : value;
      }
      ++values;
    }
    if (values != pcd.valuesPerLine) {
      throw InputError(path_, input_.lineNumber(),
                       "expected " + std::to_string(pcd.valuesPerLine) + " values (" +
                           std::to_string(pcd.fields.size()) + " fields), found " + std::to_string(values));
    }
  }

  /// Binary: the next `want` records.
  std::size_t ReadBinary(std::size_t want, PointChunk* chunk) {
    const PcdLayout& pcd = layout_.pcd;
    const std::size_t length = pcd.pointBytes;
    if (keepRaw_) chunk->raw.reserve(chunk->raw.size() + want * length);
    std::size_t count = 0;
    while (count < want) {
      if (!input_.Fill(length)) {
        throw InputError(path_, 0,
                         "the file ends inside point " + std::to_string(done_ + count) + " of " +
                             std::to_string(pcd.points));
      }
      const std::size_t records = std::min(want - count, input_.available() / length);
      const char* p = input_.data();
      for (std::size_t r = 0; r < records; ++r, p += length) {
        for (int axis = 0; axis < dim_; ++axis) {
          const PcdField& field = pcd.fields[static_cast<std::size_t>(pcd.coordinateField[axis])];
          chunk->xyz.push_back(PcdValue(p + field.offset, field.type, field.size));
        }
      }
      if (keepRaw_) {
        chunk->raw.append(input_.data(), records * length);
        for (std::size_t r = 0; r < records; ++r) chunk->rawOffsets.push_back(chunk->rawOffsets.back() + length);
      }
      input_.Consume(records * length);
      count += records;
    }
    return count;
  }

  /// Binary_compressed: checks the sizes, makes one pass over the LZF data
  /// to find where each field's column starts (and that the data is whole),
  /// and keeps a stream at the start of every column the reader needs.
  void OpenCompressedStreams() {
    const PcdLayout& pcd = layout_.pcd;
    if (input_.size() < 0) throw InputError(path_, 0, "binary_compressed data needs a regular file");
    if (!input_.Fill(8)) throw InputError(path_, 0, "the file ends before the binary_compressed sizes");
    const auto compressedSize = LoadValue<std::uint32_t>(input_.data(), false);
    const auto uncompressedSize = LoadValue<std::uint32_t>(input_.data() + 4, false);
    if (pcd.points > UINT32_MAX / pcd.storedPointBytes || uncompressedSize != pcd.points * pcd.storedPointBytes) {
      throw InputError(path_, 0,
                       "the binary_compressed data holds " + std::to_string(uncompressedSize) + " bytes, not POINTS (" +
                           std::to_string(pcd.points) + ") x " + std::to_string(pcd.storedPointBytes) +
                           " bytes per point");
    }
    const auto begin = static_cast<std::uint64_t>(input_.offset()) + 8;
    if (compressedSize > static_cast<std::uint64_t>(input_.remaining()) - 8) {
      throw InputError(path_, 0,
                       "the " + std::to_string(compressedSize) + " bytes of binary_compressed data from byte " +
                           std::to_string(begin) + " run past the end of the file");
    }
    auto file = std::make_shared<const PositionalFile>(path_);
    LzfStream scan(file, begin, compressedSize, uncompressedSize);
    std::uint64_t columnStart = 0;
    streamOfField_.assign(pcd.fields.size(), -1);
    for (std::size_t f = 0; f < pcd.fields.size(); ++f) {
      const PcdField& field = pcd.fields[f];
      if (field.isPadding()) continue;
      const bool coordinate = std::find(std::begin(pcd.coordinateField), std::begin(pcd.coordinateField) + dim_,
                                        static_cast<int>(f)) != std::begin(pcd.coordinateField) + dim_;
      if (keepRaw_ || coordinate) {
        scan.Skip(columnStart - scan.produced());
        streamOfField_[f] = static_cast<int>(streams_.size());
        streams_.push_back(scan);
        streamBytes_.push_back(field.bytes());
      }
      columnStart += pcd.points * field.bytes();
    }
    scan.Skip(uncompressedSize - scan.produced());
    scan.ExpectEnd();
    columns_.resize(streams_.size());
  }

  /// Binary_compressed: the next `want` points, a column piece per stream.
  std::size_t ReadCompressed(std::size_t want, PointChunk* chunk) {
    const PcdLayout& pcd = layout_.pcd;
    for (std::size_t s = 0; s < streams_.size(); ++s) {
      columns_[s].resize(want * streamBytes_[s]);
      streams_[s].Read(columns_[s].data(), columns_[s].size());
    }
    for (std::size_t i = 0; i < want; ++i) {
      for (int axis = 0; axis < dim_; ++axis) {
        const auto f = static_cast<std::size_t>(pcd.coordinateField[axis]);
        const PcdField& field = pcd.fields[f];
        const auto s = static_cast<std::size_t>(streamOfField_[f]);
        chunk->xyz.push_back(PcdValue(columns_[s].data() + i * streamBytes_[s], field.type, field.size));
      }
    }
    if (keepRaw_) {
      // With raw records every stored field has a stream, in field order.
      chunk->raw.reserve(chunk->raw.size() + want * pcd.storedPointBytes);
      for (std::size_t i = 0; i < want; ++i) {
        for (std::size_t s = 0; s < streams_.size(); ++s) {
          chunk->raw.append(columns_[s].data() + i * streamBytes_[s], streamBytes_[s]);
        }
        chunk->rawOffsets.push_back(chunk->raw.size());
      }
    }
    return want;
  }

  InputBuffer input_;       ///< The file, positioned at the next ascii line or binary record.
  std::uint64_t done_ = 0;  ///< Points read so far.
  /// Binary_compressed: one stream per column read, at its next point.
  std::vector<LzfStream> streams_;
  std::vector<std::size_t> streamBytes_;      ///< Bytes per point of each stream's field.
  std::vector<int> streamOfField_;            ///< Stream index of each field, -1 if none.
  std::vector<std::vector<char>> columns_;    ///< Scratch: each stream's bytes for a chunk.
};

}  // namespace

std::unique_ptr<PointReader> OpenPcdPointReader(const std::string& path, const PointReadOptions& options) {
  return std::make_unique<PcdPointReader>(path, options);
}

}  // namespace invmap::io
