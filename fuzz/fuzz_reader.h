// What every libFuzzer target of fuzz/ shares: one reader on arbitrary
// bytes. A reader may accept the input or throw io::InputError; anything
// else (a crash, another exception, a sanitizer report, a hang, memory
// beyond the run's -rss_limit_mb) is a bug. What a geometry reader accepts
// must then build or be refused with a message.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>

#include "invmap/invmap.h"
#include "io/input_error.h"
#include "io/point_reader.h"

namespace invmap::fuzz {

/// Runs `read(const std::string& bytes)`, then builds what it returns.
template <typename Read>
int FuzzGeometryReader(const std::uint8_t* data, std::size_t size, Read&& read) {
  try {
    const Geometry geometry = read(std::string(reinterpret_cast<const char*>(data), size));
    const BuildResult built = Manifold::Build(geometry);
    (void)built;
  } catch (const io::InputError&) {
  }
  return 0;
}

/// Reads the bytes as a point file named with `extension`, through a
/// temporary file (the point readers stream from paths), chunk by chunk.
inline int FuzzPointReader(const std::uint8_t* data, std::size_t size, const char* extension) {
  const std::string path = "/tmp/invmap_fuzz_" + std::to_string(::getpid()) + extension;
  if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  try {
    auto reader = io::OpenPointReader(path, io::PointReadOptions{});
    io::PointChunk chunk;
    while (reader->ReadChunk(4096, &chunk)) {
    }
  } catch (const io::InputError&) {
  }
  std::remove(path.c_str());
  return 0;
}

}  // namespace invmap::fuzz
