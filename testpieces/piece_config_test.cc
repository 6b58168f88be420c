// Test-piece configuration YAML: defaults, round trip, errors with lines.
#include <gtest/gtest.h>

#include <fstream>

#include "testpieces/piece_config.h"

namespace tpcal::testpieces {
namespace {

TEST(PieceConfig, EmptyTextIsThePaperPiece) {
  auto c = ParsePieceConfig("", "<empty>");
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  const auto& p = std::get<TurningPieceParams>(c->params);
  EXPECT_EQ(p.hole_count, 16);
  EXPECT_EQ(p.steps[0].radius_mm, 160.0);
  EXPECT_EQ(p.groove_bottom_z_mm, 405.702);
  EXPECT_EQ(c->probing.points_per_circle, 16);
}

TEST(PieceConfig, RoundTripOfEveryPiece) {
  std::vector<PieceConfig> configs(5);
  TurningPieceParams t;
  t.hole_count = 12;
  t.groove_inner_wall_pass = true;
  t.steps[4].probe_z_mm = 151.25;
  t.name = "a \"quoted\" name";
  configs[0].params = t;
  configs[0].probing = ProbingOptions::Dense();
  configs[0].process.tool_change_s = 12.5;
  configs[1].params = ContourPieceParams::ForSize(160.0);
  configs[2].params = ContourPieceParams::ForSize(320.0);
  FaceMillingPieceParams m2;
  m2.passes = 3;
  m2.overlap_fraction = 0.25;
  configs[3].params = m2;
  ConeFrustumParams cone;
  cone.axis_tilt_deg = 0.1 + 0.2;  // not representable exactly: 17 digits needed
  configs[4].params = cone;
  for (const PieceConfig& c : configs) {
    const std::string text = FormatPieceConfig(c);
    auto back = ParsePieceConfig(text, "<round trip>");
    ASSERT_TRUE(back.ok()) << back.status().ToString() << "\n" << text;
    EXPECT_EQ(FormatPieceConfig(*back), text);
    EXPECT_EQ(back->params.index(), c.params.index());
  }
  auto back = ParsePieceConfig(FormatPieceConfig(configs[4]), "<x>");
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(std::get<ConeFrustumParams>(back->params).axis_tilt_deg, 0.1 + 0.2);
  auto t_back = ParsePieceConfig(FormatPieceConfig(configs[0]), "<x>");
  ASSERT_TRUE(t_back.ok());
  EXPECT_EQ(std::get<TurningPieceParams>(t_back->params).name, t.name);
  EXPECT_EQ(std::get<TurningPieceParams>(t_back->params).steps[4].probe_z_mm, 151.25);
}

TEST(PieceConfig, SectionsMayBeEmptyOrAbsent) {
  auto c = ParsePieceConfig("piece: iso10791_m2\niso10791_m2:\nprobing:\n  grid_per_side: 7\n", "<t>");
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  EXPECT_EQ(std::get<FaceMillingPieceParams>(c->params).passes, 2);
  EXPECT_EQ(c->probing.grid_per_side, 7);
}

TEST(PieceConfig, SizeSelectsTheM1Defaults) {
  auto c = ParsePieceConfig("piece: iso10791_m1\niso10791_m1:\n  size_mm: 160\n", "<m1>");
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  const auto& p = std::get<ContourPieceParams>(c->params);
  EXPECT_EQ(p.square_side_mm, 140.0);
  EXPECT_EQ(p.end_mill_diameter_mm, 16.0);
}

void ExpectError(const std::string& text, std::size_t line, const std::string& fragment) {
  auto c = ParsePieceConfig(text, "tp.yaml");
  ASSERT_FALSE(c.ok()) << text;
  EXPECT_EQ(c.status().line(), line) << c.status().ToString();
  EXPECT_NE(c.status().ToString().find(fragment), std::string::npos) << c.status().ToString();
  EXPECT_EQ(c.status().file(), "tp.yaml");
}

TEST(PieceConfig, BadInputIsReportedWithItsLine) {
  ExpectError("piece: turning\nturning:\n  holes:\n    count: 16\n    pitch_radius: 140\n", 5,
              "unknown key 'turning.holes.pitch_radius'");
  ExpectError("piece: turning\nturning:\n  groove:\n    depth_mm: five\n", 4, "expected a finite number");
  ExpectError("piece: turning\nturning:\n  holes: {count: 16.5}\n", 3, "expected an integer");
  ExpectError("piece: turning\nturning:\n  groove: {inner_wall_pass: yes please}\n", 3, "expected true or false");
  ExpectError("piece: lathe\n", 1, "expected turning");
  ExpectError("schema: tpcal.other/2\n", 1, "schema");
  ExpectError("piece: turning\niso10791_m2:\n  passes: 3\n", 2, "does not match");
  ExpectError("piece: turning\nturning:\n  steps: [{radius_mm: 160}]\n", 3, "6 steps");
  ExpectError("probing:\n  points_per_circle: 16\n  points_per_circle: 8\n", 3, "duplicate key");
  ExpectError("piece: turning\nturnig:\n  a: 1\n", 2, "unknown key 'turnig'");
  // yaml-cpp reports an unclosed flow sequence where it notices it: at the end of the input.
  ExpectError("turning:\n  groove: [1, 2\n", 3, "YAML");
  // Values that parse but make no piece: validation names the key.
  auto c = ParsePieceConfig("turning:\n  holes: {count: 2}\n", "tp.yaml");
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.status().message().find("holes.count"), std::string::npos) << c.status().ToString();
}

TEST(PieceConfig, SampleFilesParseAndMatchTheDefaults) {
  const std::string dir = std::string(TPCAL_SOURCE_DIR) + "/samples/testpieces/";
  auto turning = LoadPieceConfig(dir + "turning_seed002.yaml");
  ASSERT_TRUE(turning.ok()) << turning.status().ToString();
  EXPECT_EQ(FormatPieceConfig(*turning), FormatPieceConfig(PieceConfig{}));
  for (const char* f : {"turning_enriched.yaml", "iso10791_m1_160.yaml", "iso10791_m1_320.yaml", "iso10791_m2.yaml",
                        "cone_frustum.yaml", "cone_frustum_enriched.yaml"}) {
    auto c = LoadPieceConfig(dir + f);
    EXPECT_TRUE(c.ok()) << f << ": " << c.status().ToString();
  }
  EXPECT_EQ(LoadPieceConfig(dir + "missing.yaml").status().code(), StatusCode::kIoError);
}

}  // namespace
}  // namespace tpcal::testpieces
