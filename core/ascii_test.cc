#include "core/ascii.h"

#include <gtest/gtest.h>

#include <string>

namespace tpcal {
namespace {

// Truth: only the 26 letters A-Z change; UTF-8 bytes (>= 0x80), digits and punctuation stay.
TEST(AsciiLower, LowersOnlyAsciiLetters) {
  EXPECT_EQ(AsciiLower("Feature,X,NZ"), "feature,x,nz");
  EXPECT_EQ(AsciiLower(".PLY"), ".ply");
  EXPECT_EQ(AsciiLower("\xC3\x89L\xC3\x89MENT @[`{"), "\xC3\x89l\xC3\x89ment @[`{");
  EXPECT_EQ(AsciiLower(std::string("A\0B", 3)), std::string("a\0b", 3));
  EXPECT_EQ(AsciiLower(""), "");
}

}  // namespace
}  // namespace tpcal
