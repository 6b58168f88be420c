#include "testpieces/process_effects_yaml.h"

#include <gtest/gtest.h>

namespace tpcal::testpieces {
namespace {

TEST(ProcessEffectsYaml, AbsentSectionsAreNoEffectAndAbsentKeysTheirDefaults) {
  auto none = ParseProcessEffects("schema: tpcal.process/1\n", "p.yaml");
  ASSERT_TRUE(none.ok()) << none.status().ToString();
  EXPECT_TRUE(none->empty());
  EXPECT_TRUE(ParseProcessEffects("", "p.yaml")->empty());

  auto servo = ParseProcessEffects("servo_reversal: {spike_x_um: 5, backlash_y_um: 2}\n", "p.yaml");
  ASSERT_TRUE(servo.ok()) << servo.status().ToString();
  ASSERT_TRUE(servo->servo.has_value());
  EXPECT_FALSE(servo->deflection.has_value());
  EXPECT_EQ(servo->servo->spike_x_um, 5.0);
  EXPECT_EQ(servo->servo->spike_y_um, 0.0);
  EXPECT_EQ(servo->servo->decay_deg, ServoReversalModel{}.decay_deg);
  EXPECT_EQ(servo->servo->backlash_y_um, 2.0);

  auto deflection = ParseProcessEffects("tool_deflection:\n", "p.yaml");  // a null section: the defaults
  ASSERT_TRUE(deflection.ok()) << deflection.status().ToString();
  ASSERT_TRUE(deflection->deflection.has_value());
  EXPECT_EQ(deflection->deflection->compliance_um_per_n, ToolDeflectionModel{}.compliance_um_per_n);
}

TEST(ProcessEffectsYaml, FormatReadsBackToTheSameEffects) {
  ProcessEffects e;
  ToolDeflectionModel d;
  d.compliance_um_per_n = Eigen::Vector3d(0.031, 0.0, 1.0 / 3.0);
  d.scale = 2.5;
  d.passive_ratio = 0.45;
  e.deflection = d;
  ServoReversalModel s;
  s.spike_x_um = 3.25;
  s.decay_deg = 7;
  s.backlash_x_um = 0.1;
  e.servo = s;
  const std::string text = FormatProcessEffects(e);
  auto back = ParseProcessEffects(text, "formatted");
  ASSERT_TRUE(back.ok()) << back.status().ToString() << "\n" << text;
  EXPECT_EQ(FormatProcessEffects(*back), text);
  EXPECT_EQ(back->deflection->compliance_um_per_n, d.compliance_um_per_n);  // 17 digits: exact
  EXPECT_EQ(back->servo->decay_deg, 7.0);
  EXPECT_EQ(FormatProcessEffects(ProcessEffects{}), "{}\n");
  EXPECT_TRUE(ParseProcessEffects(FormatProcessEffects(ProcessEffects{}), "empty")->empty());
}

TEST(ProcessEffectsYaml, BadInputNamesFileLineAndKey) {
  struct Case { const char* text; std::size_t line; const char* words; };
  for (const Case& c : {Case{"servo_reversal:\n  spike_x_um: 5\n  spike_z_um: 1\n", 3, "unknown key 'spike_z_um'"},
                        Case{"schema: tpcal.errors/1\n", 1, "expected tpcal.process/1"},
                        Case{"tool_defection: {}\n", 1, "unknown key 'tool_defection'"},
                        Case{"tool_deflection:\n  compliance_um_per_n: [0.02, 0.02]\n", 2, "[x, y, z]"},
                        Case{"servo_reversal: {spike_x_um: high}\n", 1, "expected a number"},
                        Case{"servo_reversal:\n  decay_deg: 0\n", 1, "decay_deg must be > 0"},
                        Case{"tool_deflection: {compliance_um_per_n: [0.02, -1, 0]}\n", 1, "compliance_um_per_n"}}) {
    auto r = ParseProcessEffects(c.text, "p.yaml");
    ASSERT_FALSE(r.ok()) << c.text;
    EXPECT_EQ(r.status().file(), "p.yaml") << c.text;
    EXPECT_EQ(r.status().line(), c.line) << c.text << r.status().ToString();
    EXPECT_NE(r.status().message().find(c.words), std::string::npos) << r.status().ToString();
  }
  EXPECT_EQ(LoadProcessEffects("/nonexistent/p.yaml").status().code(), StatusCode::kIoError);
}

TEST(ProcessEffectsYaml, SampleFilesParse) {
  const std::string dir = std::string(TPCAL_SOURCE_DIR) + "/samples/process/";
  auto servo = LoadProcessEffects(dir + "servo_glitch.yaml");
  ASSERT_TRUE(servo.ok()) << servo.status().ToString();
  ASSERT_TRUE(servo->servo.has_value());
  EXPECT_EQ(servo->servo->spike_x_um, 5.0);
  auto deflection = LoadProcessEffects(dir + "tool_deflection.yaml");
  ASSERT_TRUE(deflection.ok()) << deflection.status().ToString();
  ASSERT_TRUE(deflection->deflection.has_value());
  EXPECT_EQ(FormatProcessEffects(*deflection), FormatProcessEffects(ProcessEffects{ToolDeflectionModel{}, {}}));
}

}  // namespace
}  // namespace tpcal::testpieces
