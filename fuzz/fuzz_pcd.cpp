// libFuzzer target: the PCD point reader (ascii, binary, binary_compressed)
// and trim's PCD writer on arbitrary bytes (see read_and_trim.h).
#include "fuzz/read_and_trim.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzReadAndTrim(data, size, ".pcd");
  return 0;
}
