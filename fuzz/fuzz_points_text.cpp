// libFuzzer target: the .xyz point reader (fuzz/fuzz_reader.h).
#include "fuzz/fuzz_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return invmap::fuzz::FuzzPointReader(data, size, ".xyz");
}
