// The point reader of LAS files (.las): the records streamed in chunks,
// coordinates scaled and offset as the header says.
#pragma once

#include <memory>
#include <string>

#include "io/point_reader.h"

namespace invmap::io {

/// Opens a LAS 1.0 to 1.4 file of point data record format 0 to 10 (see
/// ReadLasHeader for what is checked before anything is read). Points are
/// 3D (the first two coordinates with options.forcedDim = 2): X * scale +
/// offset per axis. Raw records are the point data records, extra bytes
/// included.
std::unique_ptr<PointReader> OpenLasPointReader(const std::string& path, const PointReadOptions& options);

}  // namespace invmap::io
