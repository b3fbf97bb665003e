#include "io/las_reader.h"

#include <algorithm>
#include <cstdint>

#include "io/file_io.h"
#include "io/input_error.h"
#include "io/las_format.h"

namespace invmap::io {
namespace {

/// LAS point files: see OpenLasPointReader.
class LasPointReader : public PointReader {
 public:
  /// Opens `path`, checks its header and moves to the first record.
  LasPointReader(const std::string& path, const PointReadOptions& options)
      : PointReader(path, options.keepRaw), input_(path) {
    layout_.format = PointFormat::Las;
    layout_.las = ReadLasHeader(input_, path_);
    dim_ = options.forcedDim == 2 ? 2 : 3;
    totalCountHint_ = static_cast<std::int64_t>(layout_.las.pointCount);
  }

 private:
  /// See PointReader::ReadPoints.
  std::size_t ReadPoints(std::size_t maxPoints, PointChunk* chunk) override {
    const LasLayout& las = layout_.las;
    const std::size_t length = las.recordLength;
    const std::size_t want = static_cast<std::size_t>(std::min<std::uint64_t>(
        {las.pointCount - done_, maxPoints, std::max<std::size_t>(1, kMaxChunkRecordBytes / length)}));
    chunk->xyz.reserve(chunk->xyz.size() + want * static_cast<std::size_t>(dim_));
    if (keepRaw_) chunk->raw.reserve(chunk->raw.size() + want * length);
    std::size_t count = 0;
    while (count < want) {
      if (!input_.Fill(length)) {
        throw InputError(path_, 0,
                         "the file ends inside point record " + std::to_string(done_) + " of " +
                             std::to_string(las.pointCount));
      }
      // Decode every whole record in the buffer at once.
      const std::size_t records = std::min(want - count, input_.available() / length);
      const char* p = input_.data();
      for (std::size_t r = 0; r < records; ++r, p += length) {
        for (int axis = 0; axis < dim_; ++axis) {
          const auto value = LoadValue<std::int32_t>(p + 4 * axis, false);
          chunk->xyz.push_back(static_cast<double>(value) * las.scale[axis] + las.offset[axis]);
        }
      }
      if (keepRaw_) {
        chunk->raw.append(input_.data(), records * length);
        for (std::size_t r = 0; r < records; ++r) chunk->rawOffsets.push_back(chunk->rawOffsets.back() + length);
      }
      input_.Consume(records * length);
      count += records;
      done_ += records;
    }
    return count;
  }

  InputBuffer input_;      ///< The file, positioned at the next record.
  std::uint64_t done_ = 0; ///< Records read so far.
};

}  // namespace

std::unique_ptr<PointReader> OpenLasPointReader(const std::string& path, const PointReadOptions& options) {
  return std::make_unique<LasPointReader>(path, options);
}

}  // namespace invmap::io
