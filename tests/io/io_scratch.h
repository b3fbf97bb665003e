// Helpers of the point, PLY and result I/O tests: a scratch directory,
// binary byte builders and error expectations.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <iterator>
#include <string>

#include "io/input_error.h"

namespace invmap::io::scratch {

/// A scratch directory named after the running test, removed afterwards.
class ScratchDir {
 public:
  ScratchDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("invmap_io_" + std::to_string(::getpid()) + "_" + info->test_suite_name() + "_" + info->name());
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  /// Writes `content` to the file `name` in the directory; returns its path.
  std::string Write(const std::string& name, const std::string& content) const {
    const std::string file = Path(name);
    std::ofstream(file, std::ios::binary) << content;
    return file;
  }
  /// Path of `name` in the directory (not created).
  std::string Path(const std::string& name) const { return (path_ / name).string(); }
  /// The directory.
  const std::filesystem::path& path() const { return path_; }
  /// Number of entries in the directory (to see leftover temporary files).
  std::size_t EntryCount() const {
    return static_cast<std::size_t>(
        std::distance(std::filesystem::directory_iterator(path_), std::filesystem::directory_iterator()));
  }

 private:
  std::filesystem::path path_;
};

/// Whole content of a file.
inline std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// Appends `value` to `bytes` in big- or little-endian order.
template <class T>
void Put(std::string* bytes, T value, bool bigEndian = false) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  const std::uint16_t one = 1;
  const bool hostBig = *reinterpret_cast<const unsigned char*>(&one) == 0;
  if (bigEndian != hostBig) {
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
  }
  bytes->append(raw, sizeof(T));
}

/// Runs `read`, requires an Input-kind InputError at `line` whose message
/// holds every one of `parts`, and returns the message.
inline std::string ExpectInputError(const std::function<void()>& read, std::int64_t line,
                                    std::initializer_list<std::string> parts) {
  try {
    read();
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(e.line(), line) << message;
    EXPECT_EQ(e.kind(), InputError::Kind::Input);
    for (const std::string& part : parts) {
      EXPECT_NE(message.find(part), std::string::npos) << message << "\nlacks: " << part;
    }
    return message;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected InputError, got: " << e.what();
    return {};
  }
  ADD_FAILURE() << "no error";
  return {};
}

/// Runs `fn`, expects an InputError of `kind` whose file is `file` and line
/// `line` (-1: any) and whose message contains `part`; returns the message.
inline std::string ExpectInputError(const std::function<void()>& fn, const std::string& file, std::int64_t line,
                                    const std::string& part, InputError::Kind kind = InputError::Kind::Input) {
  try {
    fn();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), file) << e.what();
    if (line >= 0) {
      EXPECT_EQ(e.line(), line) << e.what();
    }
    EXPECT_EQ(e.kind(), kind) << e.what();
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << "message: " << e.what() << "\nexpected: " << part;
    return e.what();
  }
  ADD_FAILURE() << "no InputError (expected one containing '" << part << "')";
  return "";
}

}  // namespace invmap::io::scratch
