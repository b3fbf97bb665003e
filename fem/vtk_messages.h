// VTK reports problems through its global output window (stderr by
// default). While a file is read, invmap collects them instead, to put them
// in its own error message and keep stderr clean.
#pragma once

#include <memory>
#include <mutex>
#include <string>

namespace invmap::fem {

/// Redirects VTK's messages for its lifetime and serializes VTK file reads
/// (the output window is global): one at a time in the process.
class ScopedVtkMessages {
 public:
  ScopedVtkMessages();
  ~ScopedVtkMessages();
  ScopedVtkMessages(const ScopedVtkMessages&) = delete;
  ScopedVtkMessages& operator=(const ScopedVtkMessages&) = delete;

  /// The first error VTK reported since construction, without VTK's
  /// source-location prefix; empty when none.
  std::string FirstError() const;

 private:
  struct Impl;
  std::unique_lock<std::mutex> lock_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace invmap::fem
