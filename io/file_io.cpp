#include "io/file_io.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "io/input_error.h"

namespace invmap::io {
namespace {

/// Bytes read from the input at a time: large enough that system calls cost
/// nothing next to parsing, small enough to stay in cache.
constexpr std::size_t kReadBlock = std::size_t{1} << 20;

/// Output buffer size; WriteAt/ReadAt flush it first.
constexpr std::size_t kWriteBlock = std::size_t{1} << 20;

/// Bytes after which Flush starts the writeback of the output.
constexpr std::int64_t kWritebackBlock = std::int64_t{64} << 20;

/// Distinguishes temporary files of several outputs of one process.
std::atomic<unsigned> tempCounter{0};

/// Symbolic links followed before a target counts as a loop (the kernel's
/// own limit).
constexpr int kMaxLinkHops = 40;

/// The file that writing to `path` reaches: its last component's symbolic
/// links followed (a link to a link too; directories in between the kernel
/// follows itself). A dangling link gives the path it points to.
std::filesystem::path FollowLinks(const std::string& path) {
  std::filesystem::path file(path);
  for (int hop = 0; hop < kMaxLinkHops; ++hop) {
    std::error_code ec;
    if (!std::filesystem::is_symlink(std::filesystem::symlink_status(file, ec))) return file;
    const std::filesystem::path target = std::filesystem::read_symlink(file, ec);
    if (ec) return file;
    file = target.is_absolute() ? target : file.parent_path() / target;
  }
  errno = ELOOP;
  throw InputError(path, 0, std::string("cannot write: ") + std::strerror(errno), InputError::Kind::Output);
}

/// The temporary files a signal handler removes. A handler may neither
/// allocate nor lock, so this is a fixed table of paths, each slot Free,
/// Writing (its path changing) or Live; only Live paths are removed.
struct SignalSlot {
  enum State { Free, Writing, Live };
  std::atomic<int> state{Free};
  char path[4096];
};
constexpr int kSignalSlots = 64;
SignalSlot signalSlots[kSignalSlots];
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads the slots' states");

/// Makes `path` the slot's file (slot -1: none). Paths too long for a slot
/// are left out of the table: such a file survives a signal.
void SetSignalSlot(int slot, const std::string& path) {
  if (slot < 0) return;
  SignalSlot& entry = signalSlots[slot];
  entry.state.store(SignalSlot::Writing);
  if (path.size() >= sizeof entry.path) return;
  std::memcpy(entry.path, path.c_str(), path.size() + 1);
  entry.state.store(SignalSlot::Live);
}

/// A free slot for `path`, or -1 when all are taken.
int ClaimSignalSlot(const std::string& path) {
  for (int i = 0; i < kSignalSlots; ++i) {
    int expected = SignalSlot::Free;
    if (signalSlots[i].state.compare_exchange_strong(expected, SignalSlot::Writing)) {
      SetSignalSlot(i, path);
      return i;
    }
  }
  return -1;
}

void ReleaseSignalSlot(int slot) {
  if (slot >= 0) signalSlots[slot].state.store(SignalSlot::Free);
}

/// Removes every live temporary file, then lets `signo` end the process as
/// it would have without this handler: the default action is restored only
/// after the files are gone (a second signal meanwhile, which `timeout`
/// sends to the whole process group, runs this handler again in another
/// thread rather than ending the process halfway), and the signal, blocked
/// until the handler returns, is then delivered.
extern "C" void RemoveTemporaryFilesAndStop(int signo) {
  const int savedErrno = errno;
  for (SignalSlot& slot : signalSlots) {
    if (slot.state.load() == SignalSlot::Live) ::unlink(slot.path);
  }
  ::signal(signo, SIG_DFL);
  ::raise(signo);
  errno = savedErrno;
}

/// Opens `path` for reading bytes as stored. Throws InputError when it does
/// not exist, is a directory or cannot be opened. *size is the file's length,
/// or -1 when it is not a regular file (a pipe, a device).
std::unique_ptr<std::ifstream> OpenInputFile(const std::string& path, std::int64_t* size) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (status.type() == std::filesystem::file_type::not_found) throw InputError(path, 0, "cannot open: no such file");
  if (ec) throw InputError(path, 0, "cannot open: " + ec.message());
  // Opening a directory succeeds on Linux and only the first read fails, so
  // say what is wrong before that.
  if (std::filesystem::is_directory(status)) throw InputError(path, 0, "is a directory, not a file");
  auto file = std::make_unique<std::ifstream>(path, std::ios::binary);
  if (!file->is_open()) {
    throw InputError(path, 0, std::string("cannot open: ") + std::strerror(errno));
  }
  *size = -1;
  if (std::filesystem::is_regular_file(status)) {
    *size = static_cast<std::int64_t>(std::filesystem::file_size(path, ec));
    if (ec) *size = -1;
  }
  return file;
}

}  // namespace

bool ParseDouble(std::string_view token, double* value) {
  // from_chars takes no '+', which C's strtod and most writers allow.
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  const auto result = std::from_chars(token.data(), end, *value);
  // An out-of-range value is reported as an error by from_chars; strtod
  // would give +-inf or 0, which is what a text file means by 1e999.
  if (result.ec == std::errc::result_out_of_range && result.ptr == end) {
    *value = std::strtod(std::string(token).c_str(), nullptr);
    return true;
  }
  return result.ec == std::errc() && result.ptr == end && !token.empty();
}

bool ParseInteger(std::string_view token, std::int64_t* value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  const auto result = std::from_chars(token.data(), end, *value);
  return result.ec == std::errc() && result.ptr == end && !token.empty();
}

std::string LowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

std::string ReadWholeFile(const std::string& path, std::uint64_t maxBytes) {
  std::int64_t size = -1;  // ReadWholeStream sizes the stream itself
  const std::unique_ptr<std::ifstream> in = OpenInputFile(path, &size);
  return ReadWholeStream(*in, path, maxBytes);
}

std::string ReadWholeStream(std::istream& in, const std::string& nameForMessages, std::uint64_t maxBytes) {
  std::string bytes;
  const auto tooLarge = [&] {
    const std::string limit = maxBytes % (1 << 20) == 0 ? std::to_string(maxBytes >> 20) + " MiB"
                                                         : std::to_string(maxBytes) + " bytes";
    return InputError(nameForMessages, 0, "more than " + limit + ", more than a file of this kind ever holds");
  };
  // Seekable streams (files) are sized once, which spares the copies of
  // growing a 100 MB string.
  const std::istream::pos_type start = in.tellg();
  if (start != std::istream::pos_type(-1)) {
    if (in.seekg(0, std::ios::end)) {
      const std::istream::pos_type end = in.tellg();
      if (end != std::istream::pos_type(-1) && end >= start) {
        const auto size = static_cast<std::uint64_t>(end - start);
        if (size > maxBytes) throw tooLarge();
        bytes.reserve(static_cast<std::size_t>(size));
      }
    }
    in.clear();
    in.seekg(start);
  }
  char chunk[1 << 16];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    bytes.append(chunk, static_cast<std::size_t>(in.gcount()));
    if (bytes.size() > maxBytes) throw tooLarge();
  }
  if (in.bad()) throw InputError(nameForMessages, 0, "read error after " + std::to_string(bytes.size()) + " bytes");
  return bytes;
}

InputBuffer::InputBuffer(const std::string& path) : name_(path) { stream_ = OpenInputFile(path, &size_); }

InputBuffer::InputBuffer(std::unique_ptr<std::istream> stream, std::string name)
    : name_(std::move(name)), stream_(std::move(stream)) {
  const auto start = stream_->tellg();
  if (start != std::streampos(-1) && stream_->seekg(0, std::ios::end)) {
    const auto end = stream_->tellg();
    stream_->seekg(start);
    if (end != std::streampos(-1)) size_ = static_cast<std::int64_t>(end - start);
  }
  stream_->clear();
}

bool InputBuffer::ReadMore() {
  if (eof_) return false;
  if (begin_ > 0) {
    // Keep unconsumed bytes at the front so a record or line is contiguous.
    std::memmove(buffer_.data(), buffer_.data() + begin_, end_ - begin_);
    end_ -= begin_;
    begin_ = 0;
  }
  if (buffer_.size() - end_ < kReadBlock / 2) buffer_.resize(std::max(kReadBlock, 2 * buffer_.size()));
  stream_->read(buffer_.data() + end_, static_cast<std::streamsize>(buffer_.size() - end_));
  const auto got = static_cast<std::size_t>(stream_->gcount());
  if (stream_->bad()) throw InputError(name_, 0, "read error");
  if (got == 0) {
    eof_ = true;
    return false;
  }
  end_ += got;
  return true;
}

bool InputBuffer::Fill(std::size_t n) {
  if (available() >= n) return true;
  if (size_ >= 0 && static_cast<std::uint64_t>(n) > static_cast<std::uint64_t>(remaining())) return false;
  while (available() < n) {
    if (begin_ + n > buffer_.size()) {
      if (begin_ > 0) {
        std::memmove(buffer_.data(), buffer_.data() + begin_, end_ - begin_);
        end_ -= begin_;
        begin_ = 0;
      }
      // With a known size the input holds n bytes (checked above). With an
      // unknown size the buffer only doubles, so it stays within twice the
      // bytes actually read, whatever n a corrupt count asks for.
      if (n > buffer_.size()) buffer_.resize(size_ >= 0 ? n : std::min(n, std::max(kReadBlock, 2 * buffer_.size())));
    }
    if (!ReadMore()) return false;
  }
  return true;
}

bool InputBuffer::Skip(std::uint64_t n) {
  while (n > 0) {
    if (available() == 0 && !ReadMore()) return false;
    const std::size_t step = static_cast<std::size_t>(std::min<std::uint64_t>(n, available()));
    Consume(step);
    n -= step;
  }
  return true;
}

bool InputBuffer::ReadLine(std::string_view* line, std::string_view* raw) {
  std::size_t scanned = 0;
  const char* newline = nullptr;
  for (;;) {
    if (available() > scanned) {
      newline = static_cast<const char*>(std::memchr(data() + scanned, '\n', available() - scanned));
      if (newline != nullptr) break;
    }
    scanned = available();
    if (scanned > kMaxLineBytes) {
      throw InputError(name_, lineNumber_ + 1, "line longer than 64 MiB (not a text file?)");
    }
    if (!ReadMore()) break;
  }
  if (newline == nullptr && available() == 0) return false;
  const std::size_t rawLength = newline != nullptr ? static_cast<std::size_t>(newline - data()) + 1 : available();
  std::size_t length = newline != nullptr ? rawLength - 1 : rawLength;
  if (length > 0 && data()[length - 1] == '\r') --length;
  *line = std::string_view(data(), length);
  if (raw != nullptr) *raw = std::string_view(data(), rawLength);
  Consume(rawLength);
  ++lineNumber_;
  return true;
}

AtomicOutput::AtomicOutput(std::string path) : path_(std::move(path)) {
  std::error_code ec;
  if (std::filesystem::is_directory(path_, ec)) {
    throw InputError(path_, 0, "cannot write: is a directory", InputError::Kind::Output);
  }
  const std::filesystem::path target = FollowLinks(path_);
  filePath_ = target.string();
  // Replacing an existing output by a rename would bypass what it says of
  // itself: a pipe or device would become a plain file (its reader left
  // waiting), a read-only file would be replaced, a private one turn
  // readable by all. So those are refused, and a replacement keeps the
  // old file's permissions.
  struct stat existing {};
  const bool replaces = ::stat(filePath_.c_str(), &existing) == 0;
  if (replaces && !S_ISREG(existing.st_mode)) {
    throw InputError(path_, 0, "cannot write: not a regular file (results are written whole, then renamed into place)",
                     InputError::Kind::Output);
  }
  if (replaces && ::access(filePath_.c_str(), W_OK) != 0) Fail("cannot write");
  const std::filesystem::path dir = target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
  // A hidden name in the target's directory: the rename stays on one file
  // system, and a crash leaves a dot file, not a plausible output. The name
  // is in the signal handler's table before the file exists, so no signal
  // can come between the two and leave it behind.
  for (int attempt = 0; attempt < 100 && fd_ < 0; ++attempt) {
    tempPath_ = (dir / ("." + target.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                        std::to_string(tempCounter.fetch_add(1))))
                    .string();
    if (signalSlot_ < 0) {
      signalSlot_ = ClaimSignalSlot(tempPath_);
    } else {
      SetSignalSlot(signalSlot_, tempPath_);
    }
    fd_ = ::open(tempPath_.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd_ < 0 && errno != EEXIST) break;
  }
  if (fd_ < 0) {
    const int error = errno;
    ReleaseSignalSlot(signalSlot_);
    errno = error;
    Fail("cannot create a file in '" + dir.string() + "'");
  }
  if (replaces && ::fchmod(fd_, existing.st_mode & 07777) != 0) Fail("cannot keep the permissions of the file replaced");
  buffer_.resize(kWriteBlock);
}

AtomicOutput::~AtomicOutput() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_) ::unlink(tempPath_.c_str());
  ReleaseSignalSlot(signalSlot_);
}

void AtomicOutput::Fail(const std::string& what) const {
  throw InputError(path_, 0, what + ": " + std::strerror(errno), InputError::Kind::Output);
}

void AtomicOutput::Flush() {
  std::size_t done = 0;
  while (done < used_) {
    const ssize_t n = ::write(fd_, buffer_.data() + done, used_ - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) Fail("cannot write");
    done += static_cast<std::size_t>(n);
  }
  flushed_ += static_cast<std::int64_t>(used_);
  used_ = 0;
#ifdef __linux__
  // Start writing back what is complete so that the sync in Commit waits for
  // the tail only, not for the whole file (the disk works while results are
  // computed). A hint: its failure changes nothing.
  if (flushed_ - writebackStart_ >= kWritebackBlock) {
    ::sync_file_range(fd_, writebackStart_, flushed_ - writebackStart_, SYNC_FILE_RANGE_WRITE);
    writebackStart_ = flushed_;
  }
#endif
}

void AtomicOutput::Write(const void* data, std::size_t n) {
  const char* bytes = static_cast<const char*>(data);
  while (n > 0) {
    if (used_ == buffer_.size()) Flush();
    const std::size_t step = std::min(n, buffer_.size() - used_);
    std::memcpy(buffer_.data() + used_, bytes, step);
    used_ += step;
    bytes += step;
    n -= step;
  }
}

char* AtomicOutput::Reserve(std::size_t n) {
  if (buffer_.size() - used_ < n) {
    Flush();
    if (buffer_.size() < n) buffer_.resize(n);
  }
  return buffer_.data() + used_;
}

void AtomicOutput::WriteAt(std::int64_t offset, const void* data, std::size_t n) {
  Flush();
  const char* bytes = static_cast<const char*>(data);
  while (n > 0) {
    const ssize_t k = ::pwrite(fd_, bytes, n, static_cast<off_t>(offset));
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) Fail("cannot write");
    bytes += k;
    offset += k;
    n -= static_cast<std::size_t>(k);
  }
}

void AtomicOutput::ReadAt(std::int64_t offset, void* data, std::size_t n) {
  Flush();
  char* bytes = static_cast<char*>(data);
  while (n > 0) {
    const ssize_t k = ::pread(fd_, bytes, n, static_cast<off_t>(offset));
    if (k < 0 && errno == EINTR) continue;
    if (k < 0) Fail("cannot read back the temporary file");
    if (k == 0) {
      errno = EIO;
      Fail("cannot read back the temporary file");
    }
    bytes += k;
    offset += k;
    n -= static_cast<std::size_t>(k);
  }
}

void AtomicOutput::Commit() {
  Flush();
  // Without the sync a crash after the rename could leave an empty target,
  // breaking "complete or absent".
  if (::fsync(fd_) != 0) Fail("cannot write");
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) Fail("cannot write");
  if (::rename(tempPath_.c_str(), filePath_.c_str()) != 0) Fail("cannot rename the temporary file onto the output");
  committed_ = true;
  ReleaseSignalSlot(signalSlot_);
  signalSlot_ = -1;
}

void RemoveTemporaryFilesOnSignals() {
  static constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};
  struct sigaction action {};
  action.sa_handler = RemoveTemporaryFilesAndStop;
  // The others wait while one runs: each would end the process its own way.
  sigemptyset(&action.sa_mask);
  for (const int signo : kSignals) sigaddset(&action.sa_mask, signo);
  for (const int signo : kSignals) ::sigaction(signo, &action, nullptr);
}

}  // namespace invmap::io
