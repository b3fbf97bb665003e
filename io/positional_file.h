// A file read at any offset, for readers and writers that visit parts of
// an input out of order (LZF columns of a PCD file, the tail of a LAS file).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace invmap::io {

/// A file opened for reading at any offset (pread), shared by the streams
/// that read parts of it.
class PositionalFile {
 public:
  /// Opens `path`; throws InputError naming it when that fails.
  explicit PositionalFile(const std::string& path);
  ~PositionalFile();
  PositionalFile(const PositionalFile&) = delete;
  PositionalFile& operator=(const PositionalFile&) = delete;

  /// Reads up to n bytes at `offset` into `out`; returns how many (0 at the
  /// end of the file). Throws InputError on a read error.
  std::size_t ReadAt(std::uint64_t offset, char* out, std::size_t n) const;
  /// The file's name in messages.
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace invmap::io
