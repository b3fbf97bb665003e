// libFuzzer target: the JSON geometry reader (fuzz/fuzz_reader.h).
#include "fuzz/fuzz_reader.h"
#include "io/geometry_json.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return invmap::fuzz::FuzzGeometryReader(data, size, [](const std::string& bytes) {
    std::istringstream in(bytes);
    return invmap::io::ReadGeometryJson(in, "fuzz.json");
  });
}
