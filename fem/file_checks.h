// The checks every reader makes before handing a path to a library that
// would report a missing file in its own words (or not at all).
#pragma once

#include <string>

namespace invmap::fem {

/// Throws InputError naming `path` when it does not exist, is a directory,
/// is not a regular file (a device, a pipe) or cannot be opened for reading.
void RequireReadableFile(const std::string& path);

}  // namespace invmap::fem
