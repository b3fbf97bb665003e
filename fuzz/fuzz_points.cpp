// libFuzzer target: the point readers (text, PLY, npy) on arbitrary bytes,
// through a temporary file since they stream from paths. The first byte
// picks the format. InputError is the only acceptable failure.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "io/input_error.h"
#include "io/point_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const char* const kExtensions[] = {".xyz", ".csv", ".ply", ".npy"};
  const std::string path = "/tmp/invmap_fuzz_" + std::to_string(getpid()) + kExtensions[data[0] % 4];
  if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data + 1, 1, size - 1, f);
    std::fclose(f);
  }
  try {
    auto reader = invmap::io::OpenPointReader(path, invmap::io::PointReadOptions{});
    invmap::io::PointChunk chunk;
    while (reader->ReadChunk(4096, &chunk)) {
    }
  } catch (const invmap::io::InputError&) {
  }
  std::remove(path.c_str());
  return 0;
}
