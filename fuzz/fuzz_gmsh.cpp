// libFuzzer target: the MSH geometry reader (fuzz/fuzz_reader.h).
#include "fuzz/fuzz_reader.h"
#include "io/gmsh_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return invmap::fuzz::FuzzGeometryReader(data, size, [](const std::string& bytes) {
    std::istringstream in(bytes);
    return invmap::io::ReadGmsh(in, "fuzz.msh");
  });
}
