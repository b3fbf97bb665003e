// The C++ exceptions of the Python module; module.cpp translates each to its
// Python class, with the message unchanged (the command line's, without its
// "invmap: " prefix).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace invmap::python {

/// Invalid input: a malformed geometry, points of the wrong shape or type,
/// bad options. Raised in Python as invmap.InputError, a ValueError.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A file that cannot be read at all (missing, a directory, no permission).
/// Raised in Python as invmap.FileError, an OSError.
class FileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// max_distance as given from Python: a number >= 0, else InputError.
inline double CheckedMaxDistance(double maxDistance) {
  if (std::isnan(maxDistance) || maxDistance < 0.0) {
    std::ostringstream message;
    message << "max_distance: " << maxDistance << ", expected a number >= 0";
    throw InputError(message.str());
  }
  return maxDistance;
}

/// threads as given from Python: >= 0 (0: all cores), else InputError. More
/// than the cores runs as many as the cores, so a huge count is not an error.
inline int CheckedThreads(std::int64_t threads) {
  if (threads < 0) throw InputError("threads: " + std::to_string(threads) + ", expected >= 0 (0: all cores)");
  return static_cast<int>(std::min<std::int64_t>(threads, std::numeric_limits<int>::max()));
}

}  // namespace invmap::python
