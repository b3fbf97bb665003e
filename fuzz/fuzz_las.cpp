// libFuzzer target: the LAS point reader and trim's LAS writer on arbitrary
// bytes (see read_and_trim.h).
#include "fuzz/read_and_trim.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzReadAndTrim(data, size, ".las");
  return 0;
}
