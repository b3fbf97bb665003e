// The body of the point-cloud fuzz targets: arbitrary bytes as a point file
// of one extension, read to the end and trimmed (every other point kept),
// through temporary files since the readers and writers work on paths.
// InputError is the only acceptable failure; memory stays within
// -rss_limit_mb whatever a header claims.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "io/input_error.h"
#include "io/point_reader.h"
#include "io/trim_writer.h"

inline void FuzzReadAndTrim(const std::uint8_t* data, std::size_t size, const std::string& extension) {
  // Memory-backed when possible: trim syncs its output, which on a disk
  // would make each run slow.
  static const std::string directory = std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : "/tmp";
  const std::string stem = directory + "/invmap_fuzz_" + std::to_string(getpid());
  const std::string input = stem + extension;
  const std::string output = stem + "_out" + extension;
  if (std::FILE* f = std::fopen(input.c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  try {
    auto reader = invmap::io::OpenPointReader(input, invmap::io::PointReadOptions{});
    invmap::io::TrimWriter writer(output, reader->layout());
    invmap::io::PointChunk chunk;
    std::vector<unsigned char> keep;
    while (reader->ReadChunk(4096, &chunk)) {
      keep.assign(chunk.count, 0);
      for (std::size_t i = 0; i < chunk.count; i += 2) keep[i] = 1;
      writer.WriteChunk(chunk, keep.data());
    }
    writer.Finish();
  } catch (const invmap::io::InputError&) {
  }
  std::remove(input.c_str());
  std::remove(output.c_str());
}
