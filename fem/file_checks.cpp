#include "fem/file_checks.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "io/input_error.h"

namespace invmap::fem {

void RequireReadableFile(const std::string& path) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (status.type() == std::filesystem::file_type::not_found) throw io::InputError(path, 0, "cannot open: no such file");
  if (error) throw io::InputError(path, 0, "cannot open: " + error.message());
  if (std::filesystem::is_directory(status)) throw io::InputError(path, 0, "is a directory, not a file");
  // VTK and the Exodus library read files by seeking in them: a device or a
  // pipe (/dev/zero under a .vtu name kept VTK's reader busy for good) is
  // no input of theirs.
  if (!std::filesystem::is_regular_file(status)) {
    throw io::InputError(path, 0, "not a regular file (a device or a pipe): this format is read from files only");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in.is_open()) throw io::InputError(path, 0, std::string("cannot open: ") + std::strerror(errno));
}

}  // namespace invmap::fem
