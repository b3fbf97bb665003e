// Buffered sequential input, whole-file reads and all-or-nothing output
// files, shared by every reader and writer of io/. The geometry, point, PLY
// and result readers stream through InputBuffer and never load a whole file
// (inputs may be larger than memory); the small formats parsed as one text
// (implicit function lists and CSG trees, Cubit's JSON) read it with
// ReadWholeFile, up to a limit. Output goes to a temporary file
// beside the target and is renamed onto it only when complete, so a target
// is either the complete new file or untouched (docs/formats.md section 6).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <istream>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace invmap::io {

/// True on a big-endian host; every file format here names its byte order,
/// so values are swapped exactly when the file's order differs from this.
#if defined(__BYTE_ORDER__) && defined(__ORDER_BIG_ENDIAN__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
inline constexpr bool kHostBigEndian = true;
#else
inline constexpr bool kHostBigEndian = false;
#endif

/// Reverses the `size` bytes at p (size 1, 2, 4 or 8).
inline void ByteSwap(char* p, std::size_t size) {
  for (std::size_t i = 0; i < size / 2; ++i) {
    const char t = p[i];
    p[i] = p[size - 1 - i];
    p[size - 1 - i] = t;
  }
}

/// Value of type T stored at p (unaligned) in big-endian order if
/// `bigEndian`, else little-endian.
template <class T>
T LoadValue(const char* p, bool bigEndian) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, p, sizeof(T));
  if (bigEndian != kHostBigEndian) ByteSwap(bytes, sizeof(T));
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

/// Stores `value` at p (unaligned) in little-endian order.
template <class T>
void StoreLittleEndian(char* p, T value) {
  std::memcpy(p, &value, sizeof(T));
  if (kHostBigEndian) ByteSwap(p, sizeof(T));
}

/// Parses a whole token as a double: decimal or scientific notation, an
/// optional sign ('+' too), "nan" and "inf"/"infinity" in any case.
/// Returns false for anything else, including trailing characters.
bool ParseDouble(std::string_view token, double* value);

/// Parses a whole token as a decimal integer with an optional sign.
/// Returns false for anything else or on overflow.
bool ParseInteger(std::string_view token, std::int64_t* value);

/// Lower-cased extension of a path including the dot ("points.XYZ" ->
/// ".xyz"); empty when the file name has none.
std::string LowerExtension(const std::string& path);

/// The whole content of the file at `path`, bytes as stored. Throws InputError
/// when the path does not exist, is a directory or cannot be read, and when
/// it holds more than `maxBytes` (then no more than that is read: an endless
/// input, /dev/zero under a format's name, fails at once); an empty file
/// gives an empty string (each format decides what that means).
std::string ReadWholeFile(const std::string& path,
                          std::uint64_t maxBytes = std::numeric_limits<std::uint64_t>::max());

/// The rest of `in`, bytes as stored. Throws InputError naming
/// `nameForMessages` when the stream fails before its end, or holds more
/// than `maxBytes`.
std::string ReadWholeStream(std::istream& in, const std::string& nameForMessages,
                            std::uint64_t maxBytes = std::numeric_limits<std::uint64_t>::max());

/// Sequential reader of a file or stream through a buffer that grows only
/// as far as a caller asks (one record or line), so memory stays bounded
/// whatever the input size. Errors are InputError naming `name()`.
class InputBuffer {
 public:
  /// Longest text line ReadLine accepts: a longer one is a binary or
  /// corrupt file, and refusing it keeps memory bounded.
  static constexpr std::size_t kMaxLineBytes = std::size_t{64} << 20;

  /// Opens `path`. Throws InputError when it is missing, a directory or
  /// unreadable.
  explicit InputBuffer(const std::string& path);
  /// Reads `stream` (owned), named `name` in messages. size() is its length
  /// when the stream can seek, else -1.
  InputBuffer(std::unique_ptr<std::istream> stream, std::string name);

  InputBuffer(const InputBuffer&) = delete;
  InputBuffer& operator=(const InputBuffer&) = delete;

  /// File name used in messages.
  const std::string& name() const { return name_; }
  /// Total input bytes, -1 when unknown (a pipe).
  std::int64_t size() const { return size_; }
  /// Offset in the input of data()[0]: the bytes consumed so far.
  std::int64_t offset() const { return consumed_; }
  /// Input bytes from offset() to the end, -1 when the size is unknown.
  std::int64_t remaining() const { return size_ < 0 ? -1 : size_ - consumed_; }

  /// Makes at least n bytes available at data(). Returns false when fewer
  /// than n bytes are left in the input (available() then holds at least
  /// what it held before). Never allocates more than the input can supply.
  bool Fill(std::size_t n);
  /// The buffered, not yet consumed bytes; valid until the next non-const call.
  const char* data() const { return buffer_.data() + begin_; }
  /// Number of bytes at data().
  std::size_t available() const { return end_ - begin_; }
  /// Marks the first n available bytes as read (n <= available()).
  void Consume(std::size_t n) {
    begin_ += n;
    consumed_ += static_cast<std::int64_t>(n);
  }
  /// Consumes n bytes, reading through the input as needed. Returns false
  /// when the input ends first.
  bool Skip(std::uint64_t n);

  /// Reads the next line. `line` excludes the terminator ("\n" or "\r\n");
  /// `raw`, when not null, is the line with its terminator as in the input
  /// (the last line may have none). Both views are valid until the next
  /// non-const call. Returns false at the end of input. Throws InputError
  /// for a line longer than kMaxLineBytes.
  bool ReadLine(std::string_view* line, std::string_view* raw = nullptr);
  /// 1-based number of the line last returned by ReadLine (0 before any).
  std::int64_t lineNumber() const { return lineNumber_; }

 private:
  /// Reads more input into the buffer after end_; false at end of input.
  bool ReadMore();

  std::string name_;                      ///< See name().
  std::unique_ptr<std::istream> stream_;  ///< The input.
  std::int64_t size_ = -1;                ///< See size().
  std::vector<char> buffer_;              ///< Read-ahead; grows only for long lines or records.
  std::size_t begin_ = 0;                 ///< First unconsumed byte in buffer_.
  std::size_t end_ = 0;                   ///< One past the last valid byte in buffer_.
  std::int64_t consumed_ = 0;             ///< See offset().
  std::int64_t lineNumber_ = 0;           ///< See lineNumber().
  bool eof_ = false;                      ///< The stream has no more bytes.
};

/// An output file written in full or not at all: bytes go to a temporary
/// file in the target's directory (so the final rename cannot cross file
/// systems), and Commit() renames it onto the target, replacing any old
/// file atomically. Destroying the object without Commit() deletes the
/// temporary file and leaves the target as it was. A symbolic link at the
/// target is followed: the file it points to is written (created when the
/// link dangles) and the link stays. A target that exists must be a regular
/// file the process may write (a pipe, a device or a read-only file is
/// refused); the new file takes its permissions. Commit syncs the file before the
/// rename so that the guarantee holds through a system crash too; Flush
/// starts the writeback early so that the sync waits for the tail only.
/// Every failure (directory missing or not writable, disk full) throws
/// InputError of kind Output naming the target. The temporary file is also
/// removed when the process is stopped by a signal that
/// RemoveTemporaryFilesOnSignals handles.
class AtomicOutput {
 public:
  /// Creates the temporary file for `path`.
  explicit AtomicOutput(std::string path);
  /// Deletes the temporary file unless committed.
  ~AtomicOutput();

  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  /// The target path.
  const std::string& path() const { return path_; }
  /// Bytes written so far, including buffered ones: the offset of the next byte.
  std::int64_t size() const { return flushed_ + static_cast<std::int64_t>(used_); }

  /// Appends n bytes.
  void Write(const void* data, std::size_t n);
  /// Appends a string.
  void Write(std::string_view text) { Write(text.data(), text.size()); }
  /// Space for n bytes at the end of the output, to format into directly;
  /// Advance(k <= n) then appends the first k of them. Valid until the next call.
  char* Reserve(std::size_t n);
  /// Appends k bytes written into the last Reserve() space.
  void Advance(std::size_t k) { used_ += k; }

  /// Overwrites n bytes already written at `offset` (a count in a header
  /// that is known only at the end). offset + n <= size().
  void WriteAt(std::int64_t offset, const void* data, std::size_t n);
  /// Reads back n bytes already written at `offset` (a second pass over
  /// the output). offset + n <= size().
  void ReadAt(std::int64_t offset, void* data, std::size_t n);

  /// Flushes, syncs and renames the temporary file onto the target. After
  /// a throw the temporary file is gone and the target untouched.
  void Commit();

 private:
  /// Writes the buffer to the file.
  void Flush();
  /// Throws the Output error for `what`, with strerror(errno) appended.
  [[noreturn]] void Fail(const std::string& what) const;

  std::string path_;                 ///< The target as given (for messages).
  std::string filePath_;             ///< The file written: the target with its symbolic links followed.
  std::string tempPath_;             ///< The hidden temporary file beside filePath_.
  int signalSlot_ = -1;              ///< Its entry in the list the signal handler removes, or -1.
  int fd_ = -1;                      ///< The temporary file, open for reading and writing.
  std::vector<char> buffer_;         ///< Bytes not yet written.
  std::size_t used_ = 0;             ///< Bytes in buffer_ not yet written.
  std::int64_t flushed_ = 0;         ///< Bytes written to the file.
  std::int64_t writebackStart_ = 0;  ///< Start of the bytes not yet handed to writeback.
  bool committed_ = false;           ///< Renamed: the destructor leaves the file.
};

/// Installs handlers of SIGINT, SIGTERM and SIGHUP that delete the
/// temporary files of every AtomicOutput not yet committed, then end the
/// process by the same signal (the shell reports 128 + its number: 130 for
/// SIGINT, 143 for SIGTERM), so an interrupted run leaves no partial or
/// hidden file. For programs that own their signals (the command line);
/// a library user who does not call it keeps their own handlers.
void RemoveTemporaryFilesOnSignals();

}  // namespace invmap::io
