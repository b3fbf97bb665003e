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

TEST(InputError, BytesThatAreNotUtf8AreWrittenAsHex) {
  // A binary file's bytes quoted in a message: the caller may decode it as UTF-8.
  EXPECT_STREQ(InputError("m.msh", 7, "found '0.75\xff" "0.38'").what(), "m.msh:7: found '0.75\\xff0.38'");
  // A lead byte without its continuation, a lone continuation, an overlong
  // '/', a surrogate and a code point past U+10FFFF are not UTF-8.
  EXPECT_STREQ(InputError("a", 0, "\xc3x").what(), "a: \\xc3x");
  EXPECT_STREQ(InputError("a", 0, "\x80").what(), "a: \\x80");
  EXPECT_STREQ(InputError("a", 0, "\xc0\xaf").what(), "a: \\xc0\\xaf");
  EXPECT_STREQ(InputError("a", 0, "\xed\xa0\x80").what(), "a: \\xed\\xa0\\x80");
  EXPECT_STREQ(InputError("a", 0, "\xf4\x90\x80\x80").what(), "a: \\xf4\\x90\\x80\\x80");
  // Three- and four-byte sequences and one cut off at the end.
  EXPECT_STREQ(InputError("a", 0, "\xe2\x82\xac \xf0\x9f\x98\x80").what(), "a: \xe2\x82\xac \xf0\x9f\x98\x80");
  EXPECT_STREQ(InputError("a", 0, "x\xe2\x82").what(), "a: x\\xe2\\x82");
}

}  // namespace
}  // namespace invmap::io
