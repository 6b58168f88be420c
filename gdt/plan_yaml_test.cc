// Plan loading: the schema, strictness, and errors that cite file:line.
#include "gdt/plan_yaml.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace tpcal::gdt {
namespace {

using ::testing::HasSubstr;

const std::string kSamplePlan = std::string(TPCAL_SOURCE_DIR) + "/samples/plans/turning.yaml";

// A small valid plan; tests break one line at a time. Line numbers are 1-based.
const char* const kPlan =
    "schema: tpcal.inspection_plan/1\n"                  // 1
    "name: small\n"                                      // 2
    "datum_frame:\n"                                     // 3
    "  type: turning\n"                                  // 4
    "  primary: B_R\n"                                   // 5
    "  center: S_R\n"                                    // 6
    "  x_toward: H1\n"                                   // 7
    "  z_sense: {away_from: S4}\n"                       // 8
    "features:\n"                                        // 9
    "  B_R: {kind: plane}\n"                             // 10
    "  S_R: {kind: circle}\n"                            // 11
    "  H1: {kind: circle}\n"                             // 12
    "  S4: {kind: circle}\n"                             // 13
    "characteristics:\n"                                 // 14
    "  - name: conc\n"                                   // 15
    "    type: concentricity\n"                          // 16
    "    feature: S4\n"                                  // 17
    "    datum: S_R\n";                                  // 18

std::string Replace(std::string s, const std::string& from, const std::string& to) {
  const auto pos = s.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return s.replace(pos, from.size(), to);
}

TEST(ParseInspectionPlan, ReadsTheSmallPlan) {
  auto plan = ParseInspectionPlan(kPlan, "small.yaml");
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  EXPECT_EQ(plan->name, "small");
  ASSERT_TRUE(plan->datum_frame.has_value());
  EXPECT_EQ(plan->datum_frame->type, DatumFrameType::kTurning);
  EXPECT_EQ(plan->datum_frame->z_sense.rule, AxisSense::Rule::kAwayFrom);
  EXPECT_EQ(plan->datum_frame->z_sense.feature, "S4");
  ASSERT_EQ(plan->features.size(), 4u);
  EXPECT_EQ(plan->features[1].name, "S_R");
  EXPECT_EQ(plan->features[1].line, 11u);
  // With a datum frame, circles default to the datum XY projection.
  EXPECT_EQ(plan->features[1].projection, Projection::kDatumXY);
  ASSERT_EQ(plan->characteristics.size(), 1u);
  EXPECT_EQ(plan->characteristics[0].line, 15u);
  EXPECT_EQ(plan->characteristics[0].plane, Projection::kDatumXY);
}

struct BadPlan {
  const char* what;
  std::string text;
  std::size_t line;
  const char* message;
};

// Each bad plan fails with its file, line and message.
template <std::size_t N>
void ExpectErrorsCiteTheLine(const BadPlan (&cases)[N]) {
  for (const BadPlan& c : cases) {
    auto plan = ParseInspectionPlan(c.text, "bad.yaml");
    ASSERT_FALSE(plan.ok()) << c.what;
    EXPECT_EQ(plan.status().file(), "bad.yaml") << c.what;
    EXPECT_EQ(plan.status().line(), c.line) << c.what << ": " << plan.status().ToString();
    EXPECT_THAT(plan.status().message(), HasSubstr(c.message)) << c.what;
  }
}

TEST(ParseInspectionPlan, ErrorsCiteTheLine) {
  const std::string p = kPlan;
  const BadPlan cases[] = {
      {"unknown feature key", Replace(p, "  H1: {kind: circle}", "  H1: {kind: circle, radius_mm: 5}"), 12,
       "unknown key 'radius_mm'"},
      {"unknown kind", Replace(p, "  S4: {kind: circle}", "  S4: {kind: torus}"), 13, "unknown value 'torus'"},
      {"unknown top-level key", p + "extra: 1\n", 19, "unknown key 'extra'"},
      {"dangling datum", Replace(p, "    datum: S_R", "    datum: S9"), 15, "unknown feature 'S9'"},
      {"wrong datum kind", Replace(p, "    datum: S_R", "    datum: B_R"), 15, "is a plane"},
      {"number expected", p + "  - name: sz\n    type: size\n    feature: S4\n    nominal_radius_mm: big\n", 22,
       "expected a number"},
      {"key of another type", p + "    nominal_radius_mm: 5\n", 19, "unknown key 'nominal_radius_mm'"},
      {"yaml syntax", Replace(p, "  S4: {kind: circle}", "  S4: {kind: circle"), 14, "YAML"},
      {"duplicate key", Replace(p, "  type: turning\n", "  type: turning\n  type: turning\n"), 5, "given twice"},
      {"missing z_sense", Replace(p, "  z_sense: {away_from: S4}\n", ""), 4, "z_sense"},
      {"wrong schema", Replace(p, "tpcal.inspection_plan/1", "tpcal.inspection_plan/9"), 1, "not supported"},
      {"frame key of the other type", Replace(p, "  x_toward: H1\n", "  x_toward: H1\n  tertiary: H1\n"), 8,
       "does not apply"},
      {"bad nominal name", Replace(p, "datum_frame:", "nominals:\n  z_R: 405.702\ndatum_frame:"), 4,
       "must end with its unit"},
  };
  ExpectErrorsCiteTheLine(cases);
}

// A datum-target frame (ISO 5459 target areas: the cone frustum's), and its errors.
const char* const kTargetsPlan =
    "schema: tpcal.inspection_plan/1\n"                 // 1
    "name: cone\n"                                      // 2
    "datum_frame:\n"                                    // 3
    "  type: targets\n"                                 // 4
    "  primary: CONE_1\n"                               // 5
    "  center: CONE_1\n"                                // 6
    "  x_toward: CONE_1\n"                              // 7
    "  toward_first_point: true\n"                      // 8
    "  z_sense: {toward: CONE_3}\n"                     // 9
    "features:\n"                                       // 10
    "  CONE_1: {kind: circle, projection: none}\n"      // 11
    "  CONE_3: {kind: circle, projection: none}\n";     // 12

TEST(ParseInspectionPlan, ReadsATargetsFrame) {
  auto plan = ParseInspectionPlan(kTargetsPlan, "cone.yaml");
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  ASSERT_TRUE(plan->datum_frame.has_value());
  const DatumFrameSpec& f = *plan->datum_frame;
  EXPECT_EQ(f.type, DatumFrameType::kTargets);
  EXPECT_EQ(f.primary, "CONE_1");
  EXPECT_EQ(f.center, "CONE_1");
  EXPECT_EQ(f.x_toward, "CONE_1");
  EXPECT_TRUE(f.y_toward.empty());
  EXPECT_TRUE(f.toward_first_point);
  EXPECT_EQ(f.z_sense.rule, AxisSense::Rule::kToward);
  EXPECT_EQ(f.z_sense.feature, "CONE_3");
  // y_toward instead of x_toward, and toward_first_point defaults to false.
  auto y = ParseInspectionPlan(Replace(Replace(kTargetsPlan, "  x_toward: CONE_1\n", "  y_toward: CONE_3\n"),
                                       "  toward_first_point: true\n", ""),
                               "cone.yaml");
  ASSERT_TRUE(y.ok()) << y.status().ToString();
  EXPECT_EQ(y->datum_frame->y_toward, "CONE_3");
  EXPECT_TRUE(y->datum_frame->x_toward.empty());
  EXPECT_FALSE(y->datum_frame->toward_first_point);
}

TEST(ParseInspectionPlan, TargetsFrameErrorsCiteTheLine) {
  const std::string p = kTargetsPlan;
  const BadPlan cases[] = {
      {"both directions", Replace(p, "  x_toward: CONE_1\n", "  x_toward: CONE_1\n  y_toward: CONE_3\n"), 4,
       "exactly one of x_toward and y_toward"},
      {"no direction", Replace(p, "  x_toward: CONE_1\n", ""), 4, "exactly one of x_toward and y_toward"},
      {"not a boolean", Replace(p, "toward_first_point: true", "toward_first_point: yes please"), 8,
       "expected true or false"},
      {"3-2-1 key", Replace(p, "  center: CONE_1\n", "  center: CONE_1\n  secondary: CONE_3\n"), 7,
       "does not apply to a targets frame"},
      {"missing center", Replace(p, "  center: CONE_1\n", ""), 4, "missing key 'center'"},
      {"unknown feature", Replace(p, "  x_toward: CONE_1", "  x_toward: CONE_9"), 4, "unknown feature 'CONE_9'"},
  };
  ExpectErrorsCiteTheLine(cases);
  auto turning = ParseInspectionPlan(Replace(kPlan, "  x_toward: H1\n", "  x_toward: H1\n  y_toward: H1\n"), "bad.yaml");
  ASSERT_FALSE(turning.ok());
  EXPECT_EQ(turning.status().line(), 8u) << turning.status().ToString();
  EXPECT_THAT(turning.status().message(), HasSubstr("does not apply to a turning frame"));
}

TEST(LoadInspectionPlan, MissingFileIsAnIoError) {
  auto plan = LoadInspectionPlan("/nonexistent/plan.yaml");
  EXPECT_EQ(plan.status().code(), StatusCode::kIoError);
  EXPECT_EQ(plan.status().file(), "/nonexistent/plan.yaml");
}

TEST(LoadInspectionPlan, TheTurningSamplePlanCoversTable1) {
  auto plan = LoadInspectionPlan(kSamplePlan);
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  const char* const table1[] = {"t1_concentricity_Ch_SR", "t2_parallelism_B1_BR", "t3_distance_B3_BR",
                                "t4_size_S3",             "t5_concentricity_S4_SR", "t6_concentricity_S4_S1",
                                "t7_concentricity_S6_S3", "ta_circularity_S1",    "tb_circularity_S3",
                                "tc_circularity_S4",      "td_circularity_S6",    "circularity_S2",
                                "circularity_S5"};
  for (const char* name : table1) {
    bool found = false;
    for (const auto& c : plan->characteristics) found = found || c.name == name;
    EXPECT_TRUE(found) << name;
  }
  EXPECT_EQ(plan->Nominal("z_R_mm"), 405.702);
  EXPECT_EQ(plan->Nominal("z3_mm"), 380.702);
  EXPECT_EQ(plan->Nominal("r3_mm"), 170.0);
  const FeatureSpec* ch = plan->FindFeature("C_h");
  ASSERT_NE(ch, nullptr);
  EXPECT_EQ(ch->kind, FeatureKind::kPitchCircle);
  EXPECT_EQ(ch->members.size(), 16u);
}

}  // namespace
}  // namespace tpcal::gdt
