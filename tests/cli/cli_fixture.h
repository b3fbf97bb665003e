// The fixture of the command's end-to-end tests: a scratch directory per
// test and a runner of the built invmap binary.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace invmap::testing {

/// A fresh directory per test, removed afterwards.
class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           ("invmap_cli_" + std::string(info->name()) + "_" + std::to_string(getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  /// Runs invmap with `args`; returns the exit code, stdout and stderr in `out`.
  int Run(const std::string& args, std::string* out = nullptr) const {
    const std::string log = Path("run.log");
    const std::string command = std::string(INVMAP_CLI_PATH) + " " + args + " > " + log + " 2>&1 < /dev/null";
    const int status = std::system(command.c_str());
    if (out) *out = ReadFile(log);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  static std::string ReadFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }

  void WriteFile(const std::string& name, const std::string& text) const {
    std::ofstream(Path(name), std::ios::binary) << text;
  }

  std::filesystem::path dir_;
};

}  // namespace invmap::testing
