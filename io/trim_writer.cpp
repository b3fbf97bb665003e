#include "io/trim_writer.h"

#include <stdexcept>

#include "io/input_error.h"
#include "io/las_trim.h"
#include "io/npy.h"
#include "io/pcd_trim.h"

namespace invmap::io {
namespace {

/// Name of a format family with its extensions, for messages.
const char* FormatName(PointFormat format) {
  switch (format) {
    case PointFormat::Text:
      return "text (.xyz, .txt or .csv)";
    case PointFormat::Ply:
      return "PLY (.ply)";
    case PointFormat::Npy:
      return "npy (.npy)";
    case PointFormat::Las:
      return "LAS (.las)";
    case PointFormat::Pcd:
      return "PCD (.pcd)";
  }
  return "";
}

/// `path` when its extension names `format`, else throws (before the
/// temporary file is created).
const std::string& MatchingPath(const std::string& path, PointFormat format) {
  if (PointFormatOf(path, InputError::Kind::Output) != format) {
    throw InputError(
        path, 0,
        std::string("trim writes the input's format, ") + FormatName(format) + ": give the output a matching extension",
        InputError::Kind::Output);
  }
  return path;
}

/// True for a PLY header line "comment" followed by nothing but spaces.
bool IsBlankComment(const std::string& line) {
  return line.rfind("comment", 0) == 0 && line.find_first_not_of(' ', 7) == std::string::npos;
}

}  // namespace

TrimWriter::TrimWriter(const std::string& path, const PointFileLayout& layout)
    : out_(MatchingPath(path, layout.format)), format_(layout.format) {
  switch (format_) {
    case PointFormat::Text:
      out_.Write(layout.textHeader);
      break;
    case PointFormat::Npy:
      npyDescr_ = layout.npyDescr;
      npyColumns_ = layout.npyColumns;
      out_.Write(FixedNpyHeader(npyDescr_, 0, npyColumns_));
      break;
    case PointFormat::Ply: {
      const PlyHeader& header = layout.plyHeader;
      // Header line i belongs to the element whose element line is the
      // last one at or before i; lines before the first element and the
      // end_header line belong to none and are kept.
      std::size_t next = 0;  // elements whose element line is before the current line
      bool keep = true;
      for (std::size_t i = 0; i < header.lines.size(); ++i) {
        const bool isEnd = i + 1 == header.lines.size();
        if (next < header.elements.size() && header.elements[next].headerLine == i) {
          keep = next == layout.plyVertexElement;
          if (keep) {
            const std::string prefix = "element " + header.elements[next].name + " ";
            out_.Write(prefix);
            countOffset_ = out_.size();
            out_.Write(PlyPatchableCount(0) + "\n");
          }
          ++next;
          continue;
        }
        // A blank comment is the padding of a count written by invmap
        // (PlyPatchableCount): the count written here brings its own.
        if ((keep && !IsBlankComment(header.lines[i])) || isEnd) out_.Write(header.lines[i] + "\n");
      }
      break;
    }
    case PointFormat::Las:
      las_ = std::make_unique<LasTrimWriter>(layout.las, &out_);
      break;
    case PointFormat::Pcd:
      pcd_ = std::make_unique<PcdTrimWriter>(layout.pcd, &out_);
      break;
  }
}

TrimWriter::~TrimWriter() = default;

void TrimWriter::WriteChunk(const PointChunk& chunk, const unsigned char* keep) {
  if (finished_) throw std::logic_error("TrimWriter::WriteChunk after Finish");
  if (chunk.count > 0 && chunk.rawOffsets.size() != chunk.count + 1) {
    throw std::invalid_argument("TrimWriter::WriteChunk: the chunk has no raw records (open the reader with keepRaw)");
  }
  for (std::size_t i = 0; i < chunk.count; ++i) {
    if (keep[i] == 0) continue;
    // Runs of kept points are copied in one piece.
    std::size_t end = i + 1;
    while (end < chunk.count && keep[end] != 0) ++end;
    const char* records = chunk.raw.data() + chunk.rawOffsets[i];
    const std::size_t bytes = chunk.rawOffsets[end] - chunk.rawOffsets[i];
    if (pcd_) {
      pcd_->Write(records, bytes, end - i, &out_);
    } else {
      out_.Write(records, bytes);
    }
    if (las_) las_->Tally(records, end - i);
    written_ += static_cast<std::int64_t>(end - i);
    i = end - 1;
  }
}

void TrimWriter::Finish() {
  if (finished_) throw std::logic_error("TrimWriter::Finish called twice");
  if (format_ == PointFormat::Ply) {
    out_.WriteAt(countOffset_, PlyPatchableCount(written_).data(), static_cast<std::size_t>(kPlyPatchableCountBytes));
  } else if (format_ == PointFormat::Npy) {
    const std::string header = FixedNpyHeader(npyDescr_, written_, npyColumns_);
    out_.WriteAt(0, header.data(), header.size());
  } else if (las_) {
    las_->Finish(&out_);
  } else if (pcd_) {
    pcd_->Finish(&out_);
  }
  out_.Commit();
  finished_ = true;
}

}  // namespace invmap::io
