// The header of NumPy .npy files (format versions 1.0 to 3.0): parsing for
// the point reader, and a fixed-size header for streaming writers, which
// learn the row count only at the end and patch it in place.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "io/file_io.h"

namespace invmap::io {

/// The fields of an npy header dictionary.
struct NpyHeader {
  std::string descr;  ///< dtype descriptor, e.g. "<f8".
  bool fortranOrder = false;
  std::vector<std::int64_t> shape;
  std::int64_t dataOffset = 0;  ///< Bytes before the array data.
};

/// Reads and consumes the magic string, version and header dictionary at
/// the start of `input`. Throws InputError for anything that is not a
/// well-formed npy header with a plain dtype string; the dtype, order and
/// shape are left for the caller to judge.
NpyHeader ReadNpyHeader(InputBuffer& input);

/// Bytes of the header WriteNpyHeader makes: a multiple of 64, with room for
/// any row count.
inline constexpr std::size_t kNpyFixedHeaderBytes = 128;

/// A version 1.0 header for a C-order array of shape (rows, columns) of
/// dtype `descr`, padded with spaces to exactly kNpyFixedHeaderBytes so
/// that it can be rewritten with the final row count in place.
std::string FixedNpyHeader(const std::string& descr, std::int64_t rows, int columns);

}  // namespace invmap::io
