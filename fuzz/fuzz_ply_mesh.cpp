// libFuzzer target: the PLY mesh reader (fuzz/fuzz_reader.h).
#include "fuzz/fuzz_reader.h"
#include "io/ply_mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return invmap::fuzz::FuzzGeometryReader(data, size, [](const std::string& bytes) {
    return invmap::io::ReadPlyMesh(std::make_unique<std::istringstream>(bytes), "fuzz.ply");
  });
}
