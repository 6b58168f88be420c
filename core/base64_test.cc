#include "core/base64.h"

#include <gtest/gtest.h>

#include <random>
#include <string>

namespace tpcal {
namespace {

std::string Decoded(std::string_view text) {
  std::size_t bad = 0;
  auto r = DecodeBase64(text, &bad);
  return r ? *r : "BAD@" + std::to_string(bad);
}

// Truth: the test vectors of RFC 4648 section 10.
TEST(Base64, Rfc4648VectorsBothWays) {
  const std::pair<const char*, const char*> vectors[] = {{"", ""},         {"f", "Zg=="},     {"fo", "Zm8="},
                                                         {"foo", "Zm9v"}, {"foob", "Zm9vYg=="}, {"fooba", "Zm9vYmE="},
                                                         {"foobar", "Zm9vYmFy"}};
  for (const auto& [plain, coded] : vectors) {
    EXPECT_EQ(EncodeBase64(plain), coded);
    EXPECT_EQ(Decoded(coded), plain);
  }
}

TEST(Base64, BlanksAreSkippedAnywhere) {
  EXPECT_EQ(Decoded("  Zm9v\r\n  YmE\t=\n"), "fooba");
}

TEST(Base64, BadTextSaysWhere) {
  EXPECT_EQ(Decoded("Zm9v*mFy"), "BAD@4");   // outside the alphabet
  EXPECT_EQ(Decoded("Zg==Zg=="), "BAD@4");   // data after the padding
  EXPECT_EQ(Decoded("Z==="), "BAD@1");       // padding after one character
  EXPECT_EQ(Decoded("Zm9=="), "BAD@4");      // a third '=' in a group
  EXPECT_EQ(Decoded("Zm9vY"), "BAD@5");      // not whole groups
  EXPECT_EQ(Decoded("Zm9vYg="), "BAD@7");    // padding cut short
}

// Truth: decode(encode(b)) == b for random bytes of every length 0..99 (seed 7).
TEST(Base64, RoundTripsRandomBytes) {
  std::mt19937 rng(7);
  for (int n = 0; n < 100; ++n) {
    std::string b(static_cast<std::size_t>(n), '\0');
    for (char& c : b) c = static_cast<char>(rng() & 0xFF);
    EXPECT_EQ(Decoded(EncodeBase64(b)), b) << n;
  }
}

}  // namespace
}  // namespace tpcal
