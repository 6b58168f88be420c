// The whitelist checker rejects what a control would not take (or what the posts must not
// drift into), with the line: each case corrupts one line of a real posted program.
#include "gcode/dialect_check.h"

#include <gtest/gtest.h>

#include "gcode/internal/test_support.h"
#include "gcode/nc_reader.h"

namespace tpcal::gcode {
namespace {

std::string PostedCheck(Dialect d, const std::string& piece = "turning") {
  for (const auto& pc : testing::AllPieces()) {
    if (pc.id != piece) continue;
    auto tp = testing::MakePiece(pc);
    EXPECT_TRUE(tp.ok());
    auto p = PostProgram(*tp, testing::GoldenOptions(d, pc.id));
    if (!p.ok()) {
      ADD_FAILURE() << p.status().ToString();
      return "";
    }
    return p->program_text;
  }
  return "";
}

// Replaces the first occurrence of `from` after the header.
std::string Corrupt(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from, text.find("\n", text.find("TOOLS")));
  if (at == std::string::npos) {
    ADD_FAILURE() << "'" << from << "' not in the program";
    return text;
  }
  text.replace(at, from.size(), to);
  return text;
}

int LineOf(const std::string& text, const std::string& needle) {
  const std::size_t at = text.find(needle);
  if (at == std::string::npos) {
    ADD_FAILURE() << "'" << needle << "' not in the program";
    return -1;
  }
  int line = 1;
  for (std::size_t i = 0; i < at; ++i) line += text[i] == '\n';
  return line;
}

void ExpectRejected(Dialect d, const std::string& text, const std::string& needle, const std::string& why) {
  auto r = CheckDialectSyntax(text, testing::GoldenOptions(d, "turning"));
  ASSERT_FALSE(r.ok()) << "accepted: " << needle;
  EXPECT_EQ(static_cast<int>(r.status().line()), LineOf(text, needle)) << r.status().ToString();
  EXPECT_NE(r.status().message().find(why), std::string::npos) << r.status().ToString();
}

TEST(DialectCheck, FanucRejectsForeignWords) {
  const std::string text = PostedCheck(Dialect::kFanuc);
  ASSERT_TRUE(CheckDialectSyntax(text, testing::GoldenOptions(Dialect::kFanuc, "turning")).ok());
  // G76 is fine boring on Fanuc, but not a code this post writes: a drifting post is caught.
  ExpectRejected(Dialect::kFanuc, Corrupt(text, "G85", "G76"), "G76", "G76 is not in the fanuc subset");
  ExpectRejected(Dialect::kFanuc, Corrupt(text, "G85 X140.", "G85 X140"), "G85 X140 ", "decimal point");
  ExpectRejected(Dialect::kFanuc, Corrupt(text, "M08", "M64"), "M64", "M64 is not in the fanuc subset");
  ExpectRejected(Dialect::kFanuc, Corrupt(text, "G00 G43", "G00 G01 G43"), "G00 G01 G43", "two motion codes");
  ExpectRejected(Dialect::kFanuc, Corrupt(text, "(OP 2", "(op 2"), "(op 2", "lower-case");
  ExpectRejected(Dialect::kFanuc, Corrupt(text, "M06", "M06 Q1"), "M06 Q1", "address Q");
}

TEST(DialectCheck, LinuxCncSubset) {
  const std::string text = PostedCheck(Dialect::kLinuxCnc);
  ASSERT_TRUE(CheckDialectSyntax(text, testing::GoldenOptions(Dialect::kLinuxCnc, "turning")).ok());
  // On LinuxCNC G76 is a threading cycle: never for a reaming post.
  ExpectRejected(Dialect::kLinuxCnc, Corrupt(text, "G85", "G76"), "G76", "G76 is not in the linuxcnc subset");
  ExpectRejected(Dialect::kLinuxCnc, Corrupt(text, "M64 P0", "M64 P0 Q"), "M64 P0 Q", "without a number");
}

TEST(DialectCheck, SinumerikStatements) {
  const std::string text = PostedCheck(Dialect::kSinumerik);
  ASSERT_TRUE(CheckDialectSyntax(text, testing::GoldenOptions(Dialect::kSinumerik, "turning")).ok());
  ExpectRejected(Dialect::kSinumerik, Corrupt(text, "CYCLE85(", "CYCLE86("), "CYCLE86(", "not in the Sinumerik subset");
  ExpectRejected(Dialect::kSinumerik, Corrupt(text, "G0 D1", "G0 G43 H1"), "G43 H1", "G43 is not in the sinumerik subset");
  ExpectRejected(Dialect::kSinumerik, Corrupt(text, "SETMS(2)", "SETMS(3)"), "SETMS(3)", "");
  ExpectRejected(Dialect::kSinumerik, Corrupt(text, "M2=70", "M3=70"), "M3=70", "not in the Sinumerik subset");
}

TEST(DialectCheck, HeidenhainHasNoGWords) {
  const std::string text = PostedCheck(Dialect::kHeidenhain);
  ASSERT_TRUE(CheckDialectSyntax(text, testing::GoldenOptions(Dialect::kHeidenhain, "turning")).ok());
  ExpectRejected(Dialect::kHeidenhain, Corrupt(text, "L Z+", "L G0 Z+"), "L G0 Z+", "G-words do not exist");
  ExpectRejected(Dialect::kHeidenhain, Corrupt(text, "CC X+0 Y+0", "CC X0 Y+0"), "CC X0 Y+0", "not in the Heidenhain subset");
  ExpectRejected(Dialect::kHeidenhain, Corrupt(text, "Q201=", "Q202="), "Q202=", "expected Q201");
  // Line numbers run consecutively from 0.
  const std::size_t at = text.find("\n12 ");
  ASSERT_NE(at, std::string::npos);
  std::string skipped = text;
  skipped.replace(at + 1, 2, "13");
  auto r = CheckDialectSyntax(skipped, testing::GoldenOptions(Dialect::kHeidenhain, "turning"));
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("expected line number 12"), std::string::npos);
}

TEST(NcReader, RejectsWhatItDoesNotKnow) {
  const GcodeOptions o = testing::GoldenOptions(Dialect::kSinumerik, "turning");
  auto r = ReadNcProgram("%_N_X_MPF\nN10 G0 X1\nN20 POLY X2\n", o);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().line(), 3u);
  auto arc = ReadNcProgram("%\nN10 G3 X1 Y1\n%\n", testing::GoldenOptions(Dialect::kFanuc, "turning"));
  ASSERT_FALSE(arc.ok());
  EXPECT_NE(arc.status().message().find("I and J"), std::string::npos);
}

}  // namespace
}  // namespace tpcal::gcode
