#include "gcode/options_yaml.h"

#include <gtest/gtest.h>

#include "gcode/nc_format.h"

namespace tpcal::gcode {
namespace {

TEST(NcFormat, NumbersPerDialectStyle) {
  EXPECT_EQ(FormatNumber(140.0, 4), "140");
  EXPECT_EQ(FormatNumber(140.0, 4, NumberStyle::kPoint), "140.");
  EXPECT_EQ(FormatNumber(-3.5, 4, NumberStyle::kPoint), "-3.5");
  EXPECT_EQ(FormatNumber(0.0, 4, NumberStyle::kSigned), "+0");
  EXPECT_EQ(FormatNumber(-0.00001, 4), "0");  // no "-0"
  EXPECT_EQ(FormatNumber(-0.00001, 4, NumberStyle::kSigned), "+0");
  EXPECT_EQ(FormatNumber(405.70249, 4), "405.7025");
  EXPECT_EQ(FormatNumber(22.5, 4, NumberStyle::kSigned), "+22.5");
  EXPECT_EQ(SanitizeComment("a (b)\n"), "a [b] ");
}

TEST(GcodeOptions, DialectDefaults) {
  EXPECT_EQ(GcodeOptions::ForDialect(Dialect::kSinumerik).five_axis, FiveAxisMode::kToolCenterPoint);
  EXPECT_EQ(GcodeOptions::ForDialect(Dialect::kLinuxCnc).five_axis, FiveAxisMode::kJointInverseTime);
  EXPECT_EQ(GcodeOptions::ForDialect(Dialect::kFanuc).c_spindle.mode_on_mcode, 250);
  for (Dialect d : {Dialect::kFanuc, Dialect::kLinuxCnc, Dialect::kSinumerik, Dialect::kHeidenhain}) {
    EXPECT_TRUE(GcodeOptions::ForDialect(d).Validate().ok()) << DialectName(d);
    EXPECT_EQ(DialectFromName(DialectName(d)), d);
  }
}

TEST(GcodeOptionsYaml, RoundTripsEveryKey) {
  GcodeOptions o = GcodeOptions::ForDialect(Dialect::kHeidenhain);
  o.program_name = "TURN_01";
  o.date = "2024-05-01";
  o.work_offset = 3;
  o.coolant = Coolant::kMist;
  o.block_step = 5;
  o.linear_decimals = 3;
  o.tools = {{1, 12, 95.5}, {3, 0, 0.0}};
  o.c_spindle.css = false;
  o.c_spindle.max_rpm = 300;
  o.c_spindle.orient_angle_deg = 90;
  o.safety.rapid_tolerance_mm = 0.02;
  o.backplot.width_px = 800;
  const std::string yaml = FormatGcodeOptions(o);
  auto back = ParseGcodeOptions(yaml, "<roundtrip>");
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ(FormatGcodeOptions(*back), yaml);
  EXPECT_EQ(back->dialect, Dialect::kHeidenhain);
  EXPECT_EQ(back->tools.size(), 2u);
  EXPECT_EQ(back->PostedToolNumber(1), 12);
  EXPECT_EQ(back->PostedToolNumber(3), 3);
}

TEST(GcodeOptionsYaml, EmptyIsLinuxCncDefaults) {
  auto o = ParseGcodeOptions("", "<empty>");
  ASSERT_TRUE(o.ok());
  EXPECT_EQ(o->dialect, Dialect::kLinuxCnc);
  auto f = ParseGcodeOptions("dialect: fanuc\n", "<f>");
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(f->c_spindle.mode_on_mcode, 250);  // dialect defaults apply to the keys not given
}

TEST(GcodeOptionsYaml, ErrorsNameFileLineAndKey) {
  auto unknown = ParseGcodeOptions("dialect: fanuc\nc_spindle:\n  mode_on: 3\n", "post.yaml");
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.status().line(), 3u);
  EXPECT_NE(unknown.status().ToString().find("post.yaml:3"), std::string::npos);
  EXPECT_NE(unknown.status().message().find("c_spindle.mode_on"), std::string::npos);

  auto type = ParseGcodeOptions("work_offset: two\n", "post.yaml");
  ASSERT_FALSE(type.ok());
  EXPECT_EQ(type.status().line(), 1u);
  EXPECT_NE(type.status().message().find("work_offset"), std::string::npos);

  auto dialect = ParseGcodeOptions("dialect: haas\n", "post.yaml");
  ASSERT_FALSE(dialect.ok());
  EXPECT_NE(dialect.status().message().find("fanuc, linuxcnc"), std::string::npos);

  auto dup = ParseGcodeOptions("block_step: 10\nblock_step: 5\n", "post.yaml");
  ASSERT_FALSE(dup.ok());
  EXPECT_EQ(dup.status().line(), 2u);

  auto invalid = ParseGcodeOptions("dialect: heidenhain\nblock_step: 0\n", "post.yaml");
  ASSERT_FALSE(invalid.ok());
  EXPECT_EQ(invalid.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(invalid.status().message().find("block_step"), std::string::npos);

  auto tcp = ParseGcodeOptions("dialect: linuxcnc\nfive_axis: tcp\n", "post.yaml");
  ASSERT_FALSE(tcp.ok());
  EXPECT_NE(tcp.status().message().find("five_axis"), std::string::npos);

  auto schema = ParseGcodeOptions("schema: tpcal.gcode/9\n", "post.yaml");
  ASSERT_FALSE(schema.ok());

  auto half = ParseGcodeOptions("c_spindle: {mode_on_mcode: 200}\n", "post.yaml");
  ASSERT_FALSE(half.ok());
  EXPECT_NE(half.status().message().find("mode_off_mcode"), std::string::npos);
}

TEST(GcodeOptionsYaml, SampleFilesParse) {
  for (const char* name : {"fanuc", "linuxcnc", "sinumerik", "heidenhain"}) {
    auto o = LoadGcodeOptions(std::string(TPCAL_SOURCE_DIR) + "/samples/gcode/" + name + ".yaml");
    ASSERT_TRUE(o.ok()) << name << ": " << o.status().ToString();
    EXPECT_EQ(DialectName(o->dialect), std::string(name));
  }
  EXPECT_EQ(LoadGcodeOptions("/nonexistent/post.yaml").status().code(), StatusCode::kIoError);
}

}  // namespace
}  // namespace tpcal::gcode
