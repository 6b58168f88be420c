// The ball-bar file (pipeline/io/ballbar_io.h): the contract example reads, Format -> Parse keeps
// every row, and each malformed input fails at its line.
#include "pipeline/io/ballbar_io.h"

#include <gtest/gtest.h>

#include <string>

namespace tpcal::pipeline {
namespace {

constexpr const char* kBallbarContract =
    "# tpcal ballbar v1\n"
    "# units: mm\n"
    "setup,angle_deg,dl_um\n"
    "C_radial_H1,0,0.0\n"
    "C_radial_H1,20,1.8\n";

TEST(BallbarIo, ReadsTheContractExample) {
  auto f = ParseBallbar(kBallbarContract, "bb.csv");
  ASSERT_TRUE(f.ok()) << f.status().ToString();
  EXPECT_FALSE(f->has_direction);
  EXPECT_FALSE(f->has_t);
  ASSERT_EQ(f->rows.size(), 2u);
  EXPECT_EQ(f->rows[1].line, 5u);
  EXPECT_EQ(f->rows[1].setup, "C_radial_H1");
  EXPECT_EQ(f->rows[1].angle_deg, 20.0);
  EXPECT_EQ(f->rows[1].dl_um, 1.8);
  EXPECT_EQ(f->rows[1].direction, BallbarDirection::kNone);
}

TEST(BallbarIo, OptionalColumnsInAnyOrderAndRoundTrip) {
  const std::string text =
      "# tpcal ballbar v1\n"
      "t_s, direction, dl_um, angle_deg, setup\r\n"
      "\n"
      "# a comment\n"
      "12.5, ccw, -0.30000000000000004, 90, XY_circle\r\n"
      "13, cw, +2, 1e2, XY_circle\n";
  auto f = ParseBallbar(text, "c.csv");
  ASSERT_TRUE(f.ok()) << f.status().ToString();
  ASSERT_TRUE(f->has_direction && f->has_t);
  ASSERT_EQ(f->rows.size(), 2u);
  EXPECT_EQ(f->rows[0].line, 5u);
  EXPECT_EQ(f->rows[0].direction, BallbarDirection::kCcw);
  EXPECT_EQ(f->rows[0].dl_um, -0.30000000000000004);
  EXPECT_EQ(f->rows[1].direction, BallbarDirection::kCw);
  EXPECT_EQ(f->rows[1].angle_deg, 100.0);
  auto back = ParseBallbar(FormatBallbar(*f), "c.csv");
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  ASSERT_EQ(back->rows.size(), f->rows.size());
  for (std::size_t i = 0; i < f->rows.size(); ++i) {
    EXPECT_EQ(back->rows[i].setup, f->rows[i].setup);
    EXPECT_EQ(back->rows[i].angle_deg, f->rows[i].angle_deg);
    EXPECT_EQ(back->rows[i].dl_um, f->rows[i].dl_um);
    EXPECT_EQ(back->rows[i].direction, f->rows[i].direction);
    EXPECT_EQ(back->rows[i].t_s, f->rows[i].t_s);
  }
}

TEST(BallbarIo, MalformedInputFailsAtItsLine) {
  struct Bad {
    std::string text;
    std::size_t line;
    const char* message;
  };
  const std::string head = "# tpcal ballbar v1\nsetup,angle_deg,dl_um\n";
  const Bad cases[] = {
      {"# tpcal ballbar v2\n", 1, "first line"},
      {"", 1, "empty file"},
      {"# tpcal ballbar v1\n# units: in\n", 2, "units"},
      {"# tpcal ballbar v1\nsetup,angle_deg\n", 2, "header needs"},
      {"# tpcal ballbar v1\nsetup,angle_deg,dl_um,dl_um\n", 2, "repeated"},
      {"# tpcal ballbar v1\nsetup,angle_deg,dl_mm\n", 2, "unknown column"},
      {head + "a,0,1\na,1\n", 4, "expected 3 fields"},
      {head + ",0,1\n", 3, "empty setup"},
      {head + "a,zero,1\n", 3, "finite number"},
      {head + "a,0,inf\n", 3, "finite number"},
      {"# tpcal ballbar v1\nsetup,angle_deg,dl_um,direction\na,0,1,up\n", 3, "cw or ccw"},
      {"# tpcal ballbar v1\nangle_deg,setup,dl_um\n0,#a,1\n", 3, "starts with '#'"},
      {head, 2, "no readings"},
  };
  for (const Bad& c : cases) {
    auto r = ParseBallbar(c.text, "bad.csv");
    ASSERT_FALSE(r.ok()) << c.text;
    EXPECT_EQ(r.status().code(), StatusCode::kParseError);
    EXPECT_EQ(r.status().file(), "bad.csv");
    EXPECT_EQ(r.status().line(), c.line) << r.status().ToString();
    EXPECT_NE(r.status().message().find(c.message), std::string::npos) << r.status().ToString();
  }
}

TEST(BallbarIo, ReadsTheSample) {
  auto f = ReadBallbar(std::string(TPCAL_SOURCE_DIR) + "/samples/ballbar/seed003_table1_c_axis.csv");
  ASSERT_TRUE(f.ok()) << f.status().ToString();
  EXPECT_EQ(f->rows.size(), 7u * 19u);  // seed 003 Table 1: 7 measurements at 0..360 deg by 20
  auto missing = ReadBallbar("/nonexistent/ballbar.csv");
  EXPECT_FALSE(missing.ok());
}

}  // namespace
}  // namespace tpcal::pipeline
