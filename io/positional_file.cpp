#include "io/positional_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "io/input_error.h"

namespace invmap::io {

PositionalFile::PositionalFile(const std::string& path) : path_(path) {
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) throw InputError(path, 0, std::string("cannot open: ") + std::strerror(errno));
}

PositionalFile::~PositionalFile() { ::close(fd_); }

std::size_t PositionalFile::ReadAt(std::uint64_t offset, char* out, std::size_t n) const {
  std::size_t done = 0;
  while (done < n) {
    const ssize_t k = ::pread(fd_, out + done, n - done, static_cast<off_t>(offset + done));
    if (k < 0 && errno == EINTR) continue;
    if (k < 0) throw InputError(path_, 0, std::string("read error: ") + std::strerror(errno));
    if (k == 0) break;
    done += static_cast<std::size_t>(k);
  }
  return done;
}

}  // namespace invmap::io
