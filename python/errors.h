// The C++ exceptions of the Python module; module.cpp translates each to its
// Python class, with the message unchanged (the command line's, without its
// "invmap: " prefix).
#pragma once

#include <stdexcept>

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

}  // namespace invmap::python
