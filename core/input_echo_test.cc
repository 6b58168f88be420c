#include "core/input_echo.h"

#include <gtest/gtest.h>

#include <string>

namespace tpcal {
namespace {

TEST(InputEcho, PrintableUtf8PassesUnchanged) {
  EXPECT_EQ(EchoInput("feature,x,y,z"), "feature,x,y,z");
  EXPECT_EQ(EchoInput("caf\xC3\xA9 \xE2\x82\xAC"), "caf\xC3\xA9 \xE2\x82\xAC");
  EXPECT_EQ(EchoInput("a\\b"), "a\\b");
}

TEST(InputEcho, ControlBytesAndBrokenUtf8AreEscaped) {
  EXPECT_EQ(EchoInput(std::string("a\0b", 3)), "a\\x00b");
  EXPECT_EQ(EchoInput("\x1B[31mred\tx\x7F"), "\\x1B[31mred\\tx\\x7F");
  EXPECT_EQ(EchoInput("caf\xE9"), "caf\\xE9");             // Latin-1
  EXPECT_EQ(EchoInput("\xC0\xAF"), "\\xC0\\xAF");           // overlong '/'
  EXPECT_EQ(EchoInput("\xED\xA0\x80"), "\\xED\\xA0\\x80");  // surrogate
  EXPECT_EQ(EchoInput("\xE2\x82"), "\\xE2\\x82");           // cut sequence
}

TEST(InputEcho, LongInputIsCutAtACharacterBoundary) {
  EXPECT_EQ(EchoInput(std::string(1 << 20, 'a')), std::string(80, 'a') + "...");
  EXPECT_EQ(EchoInput(std::string(80, 'a')), std::string(80, 'a'));
  // A two-byte character that would straddle the limit is left out whole.
  EXPECT_EQ(EchoInput(std::string(79, 'a') + "\xC3\xA9"), std::string(79, 'a') + "...");
  EXPECT_EQ(EchoInput("abcdef", 3), "abc...");
}

TEST(InputEcho, FirstInvalidUtf8) {
  EXPECT_EQ(FirstInvalidUtf8("plain"), std::string_view::npos);
  EXPECT_EQ(FirstInvalidUtf8("caf\xC3\xA9"), std::string_view::npos);
  EXPECT_EQ(FirstInvalidUtf8("\xF0\x9F\x98\x80"), std::string_view::npos);  // U+1F600
  EXPECT_EQ(FirstInvalidUtf8("caf\xE9"), 3u);
  EXPECT_EQ(FirstInvalidUtf8("ab\xF4\x90\x80\x80"), 2u);  // above U+10FFFF
  EXPECT_EQ(FirstInvalidUtf8("\x80"), 0u);
}

}  // namespace
}  // namespace tpcal
