#include "io/reader_registry.h"

#include <algorithm>
#include <deque>
#include <mutex>
#include <vector>

#include "io/file_io.h"

namespace invmap::io {
namespace {

std::mutex& RegistryMutex() {
  static std::mutex mutex;
  return mutex;
}

/// A deque: FindRegisteredReader hands out pointers that later
/// registrations must not invalidate.
std::deque<RegisteredReader>& Registry() {
  static std::deque<RegisteredReader> readers;
  return readers;
}

}  // namespace

void RegisterGeometryReader(const RegisteredReader& reader) {
  const std::lock_guard<std::mutex> lock(RegistryMutex());
  for (const RegisteredReader& r : Registry()) {
    if (r.extension == reader.extension && r.read == reader.read) return;
  }
  Registry().push_back(reader);
}

const RegisteredReader* FindRegisteredReader(const std::string& path) {
  const std::string ext = LowerExtension(path);
  const std::lock_guard<std::mutex> lock(RegistryMutex());
  for (const RegisteredReader& r : Registry()) {
    if (r.extension == ext && (r.accepts == nullptr || r.accepts(path))) return &r;
  }
  return nullptr;
}

std::string RegisteredExtensions() {
  const std::lock_guard<std::mutex> lock(RegistryMutex());
  std::vector<std::string> seen;
  std::string list;
  for (const RegisteredReader& r : Registry()) {
    if (std::find(seen.begin(), seen.end(), r.extension) != seen.end()) continue;
    seen.push_back(r.extension);
    list += (list.empty() ? "" : ", ") + r.extension;
  }
  return list;
}

}  // namespace invmap::io
