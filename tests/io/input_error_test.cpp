// InputError's message: the file, the line and the reason, with the file's
// own bytes quoted printably (a NUL inside would otherwise end what()).
#include <gtest/gtest.h>

#include <string>

#include "io/input_error.h"

namespace invmap::io {
namespace {

TEST(InputError, NamesTheFileAndLine) {
  EXPECT_STREQ(InputError("p.xyz", 12, "expected 3 numbers, found 2").what(), "p.xyz:12: expected 3 numbers, found 2");
  EXPECT_STREQ(InputError("p.npy", 0, "not a npy file").what(), "p.npy: not a npy file");
}

TEST(InputError, ControlBytesAreWrittenAsHexAndNothingIsCutShort) {
  const std::string quoted = std::string("'0.6") + '\0' + "1' is not a finite number";
  const InputError error("poses.txt", 3, quoted);
  EXPECT_STREQ(error.what(), "poses.txt:3: '0.6\\x001' is not a finite number");
  EXPECT_STREQ(InputError("a.csv", 1, std::string("x\ty\r\x7f")).what(), "a.csv:1: x\\x09y\\x0d\\x7f");
  EXPECT_STREQ(InputError("caf\xc3\xa9.csv", 1, "bad").what(), "caf\xc3\xa9.csv:1: bad");  // UTF-8 kept
}

}  // namespace
}  // namespace invmap::io
