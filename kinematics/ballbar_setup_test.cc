// Ball-bar set-up files (kinematics/ballbar_setup.h): the sample of seed 003 reads, Format ->
// Parse keeps every field, and each malformed input fails at its line.
#include "kinematics/ballbar_setup.h"

#include <gtest/gtest.h>

#include <string>

namespace tpcal::kinematics {
namespace {

constexpr const char* kBbsText = R"(schema: tpcal.ballbar_setup/1
installations:
  - name: C_radial_H1
    kind: radial
    axis: C
    workpiece_ball_in_part_mm: [150, 0, 50]
    tool_ball_in_tool_mm: [0, 0, 0]
    nominal_length_mm: 150
    sense: -1
    hold_deg: {B: 0}
  - name: B_axial_L1
    kind: axial
    axis: B
    workpiece_ball_in_part_mm: [0, -150, -50]
    tool_ball_in_tool_mm: [0, 0, 150]
    nominal_length_mm: 150
  - name: XY_circle
    kind: circle
    axis: XY
    workpiece_ball_in_part_mm: [0, 0, 0]
    tool_ball_in_tool_mm: [0, 0, 0]
    nominal_length_mm: 100
)";

TEST(BallbarSetup, ParsesEveryField) {
  auto s = ParseBallbarSetup(kBbsText, "s.yaml");
  ASSERT_TRUE(s.ok()) << s.status().ToString();
  ASSERT_EQ(s->installations.size(), 3u);
  const BallbarInstallation& c = s->installations[0];
  EXPECT_EQ(c.name, "C_radial_H1");
  EXPECT_EQ(c.kind, BallbarKind::kRadial);
  EXPECT_EQ(c.axis, Axis::kC);
  EXPECT_EQ(c.workpiece_ball_in_part_mm, Eigen::Vector3d(150, 0, 50));
  EXPECT_EQ(c.nominal_length_mm, 150.0);
  EXPECT_EQ(c.sense, -1);
  ASSERT_EQ(c.hold_deg.count(Axis::kB), 1u);
  EXPECT_EQ(s->installations[1].sense, +1);  // default
  EXPECT_EQ(s->installations[1].tool_ball_in_tool_mm, Eigen::Vector3d(0, 0, 150));
  EXPECT_EQ(s->installations[2].kind, BallbarKind::kCircle);
  EXPECT_EQ(s->installations[2].plane, BallbarPlane::kXY);
  ASSERT_NE(s->Find("B_axial_L1"), nullptr);
  EXPECT_EQ(s->Find("nope"), nullptr);
}

void ExpectSameInstallation(const BallbarInstallation& a, const BallbarInstallation& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.axis, b.axis);
  EXPECT_EQ(a.plane, b.plane);
  EXPECT_EQ(a.workpiece_ball_in_part_mm, b.workpiece_ball_in_part_mm);
  EXPECT_EQ(a.tool_ball_in_tool_mm, b.tool_ball_in_tool_mm);
  EXPECT_EQ(a.nominal_length_mm, b.nominal_length_mm);
  EXPECT_EQ(a.sense, b.sense);
  EXPECT_EQ(a.hold_deg, b.hold_deg);
}

TEST(BallbarSetup, FormatReadsBackToTheSameSet) {
  auto s = ParseBallbarSetup(kBbsText, "s.yaml");
  ASSERT_TRUE(s.ok());
  s->installations[0].workpiece_ball_in_part_mm.x() = 0.1 + 0.2;  // 17 digits survive
  auto back = ParseBallbarSetup(FormatBallbarSetup(*s), "f.yaml");
  ASSERT_TRUE(back.ok()) << back.status().ToString() << "\n" << FormatBallbarSetup(*s);
  ASSERT_EQ(back->installations.size(), s->installations.size());
  for (std::size_t i = 0; i < s->installations.size(); ++i) ExpectSameInstallation(s->installations[i], back->installations[i]);
}

TEST(BallbarSetup, TheSeed003SampleReads) {
  auto s = LoadBallbarSetup(std::string(TPCAL_SOURCE_DIR) + "/samples/ballbar/seed003_setups.yaml");
  ASSERT_TRUE(s.ok()) << s.status().ToString();
  // Table 1: 7 C-table measurements; Table 2: 6 B-head measurements.
  EXPECT_EQ(s->installations.size(), 13u);
}

// Truth: the function's seven C-table installations are the sample's first seven, field by field.
TEST(BallbarSetup, Seed003CTableSetupIsTheSamplesCTable) {
  auto s = LoadBallbarSetup(std::string(TPCAL_SOURCE_DIR) + "/samples/ballbar/seed003_setups.yaml");
  ASSERT_TRUE(s.ok()) << s.status().ToString();
  const BallbarSetup c = Seed003CTableSetup(Axis::kB);
  ASSERT_EQ(c.installations.size(), 7u);
  for (std::size_t i = 0; i < 7; ++i) ExpectSameInstallation(c.installations[i], s->installations[i]);
  EXPECT_EQ(Seed003CTableSetup(Axis::kA).installations[0].hold_deg, (std::map<Axis, double>{{Axis::kA, 0.0}}));
}

// One line changed in kBbsText -> the error and the line it names.
struct BbsBad {
  const char* from;
  const char* to;
  std::size_t line;
  const char* message;
};

TEST(BallbarSetup, MalformedInputFailsAtItsLine) {
  const BbsBad cases[] = {
      {"schema: tpcal.ballbar_setup/1", "schema: tpcal.ballbar_setup/2", 1, "schema"},
      {"kind: radial", "kind: diagonal", 4, "kind"},
      {"axis: C", "axis: X", 5, "rotary axis"},
      {"axis: XY", "axis: XZ", 19, "plane"},
      {"nominal_length_mm: 150\n    sense", "nominal_length_mm: 0\n    sense", 8, "> 0"},
      {"sense: -1", "sense: 2", 9, "+1 or -1"},
      {"hold_deg: {B: 0}", "hold_deg: {C: 0}", 10, "turned axis"},
      {"hold_deg: {B: 0}", "hold_deg: {X: 0}", 10, "rotary axis"},
      {"name: B_axial_L1", "name: C_radial_H1", 11, "repeated"},
      {"name: XY_circle", "name: 'a,b'", 17, "comma"},
      {"    nominal_length_mm: 100\n", "    nominal_length_mm: 100\n    sense: 1\n", 23, "circle"},
      {"tool_ball_in_tool_mm: [0, 0, 150]", "tool_ball_in_tool_mm: [0, 0]", 15, "[x, y, z]"},
      {"    nominal_length_mm: 100\n", "    nominal_length_mm: 100\n    colour: red\n", 23, "unknown key"},
  };
  for (const BbsBad& c : cases) {
    std::string text = kBbsText;
    const std::size_t at = text.find(c.from);
    ASSERT_NE(at, std::string::npos) << c.from;
    text.replace(at, std::string(c.from).size(), c.to);
    auto r = ParseBallbarSetup(text, "bad.yaml");
    ASSERT_FALSE(r.ok()) << c.to;
    EXPECT_EQ(r.status().code(), StatusCode::kParseError);
    EXPECT_EQ(r.status().file(), "bad.yaml");
    EXPECT_EQ(r.status().line(), c.line) << c.to << ": " << r.status().ToString();
    EXPECT_NE(r.status().message().find(c.message), std::string::npos) << r.status().ToString();
  }
  EXPECT_FALSE(ParseBallbarSetup("", "e.yaml").ok());
  EXPECT_FALSE(ParseBallbarSetup("installations: []\n", "e.yaml").ok());
  EXPECT_FALSE(ParseBallbarSetup("installations: [\n", "e.yaml").ok());
}

}  // namespace
}  // namespace tpcal::kinematics
