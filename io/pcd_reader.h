// The point reader of PCD files (.pcd): ascii, binary and
// binary_compressed data streamed in chunks.
#pragma once

#include <memory>
#include <string>

#include "io/point_reader.h"

namespace invmap::io {

/// Opens a PCD file (see ReadPcdHeader for the header's checks). The
/// coordinates are the fields x, y and (for 3D) z, of any type; a field of
/// COUNT > 1 gives its first value. Points are 3D when there is a z field,
/// else 2D (options.forcedDim chooses). Raw records: ascii, the point's
/// line; binary, its record; binary_compressed, the values of every field
/// but "_" in field order. Binary data must hold the header's POINTS
/// (checked before anything is read; bytes after them are ignored, as PCL's
/// writers leave some); binary_compressed data must decompress to exactly
/// POINTS points (checked by a first pass over the compressed bytes, which
/// then feeds one stream per field); ascii data must have exactly POINTS
/// non-blank lines of the header's number of values, each a number.
std::unique_ptr<PointReader> OpenPcdPointReader(const std::string& path, const PointReadOptions& options);

}  // namespace invmap::io
