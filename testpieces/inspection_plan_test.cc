// The inspection plans built from the pieces' parameters: valid for every piece, and for the
// turning piece in agreement with the gdt layer's samples/plans/turning.yaml (same features,
// datum frame, characteristics and nominals), so that a dimension is written once.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "gdt/plan_yaml.h"
#include "testpieces/inspection_plan.h"
#include "testpieces/probing_plan.h"

namespace tpcal::testpieces {
namespace {

kinematics::MachineModel PlanAcTable() {
  auto m = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  EXPECT_TRUE(m.ok());
  return *m;
}

TEST(InspectionPlan, EveryPieceHasAValidPlanOverItsFeatures) {
  std::vector<PieceParams> all = {TurningPieceParams{}, ContourPieceParams::ForSize(160),
                                  ContourPieceParams::ForSize(320), FaceMillingPieceParams{}, ConeFrustumParams{}};
  for (const PieceParams& p : all) {
    PieceConfig c;
    c.params = p;
    auto piece = MakeTestPiece(c, PlanAcTable());
    ASSERT_TRUE(piece.ok()) << piece.status().ToString();
    EXPECT_TRUE(gdt::ValidatePlan(piece->inspection).ok());
    // Every probed feature of the plan is a feature of the piece (pitch circles are derived).
    for (const auto& f : piece->inspection.features) {
      if (f.kind == gdt::FeatureKind::kPitchCircle) continue;
      EXPECT_NE(piece->Feature(f.name), nullptr) << f.name;
    }
  }
}

// The datum-target frames the M2 and cone pieces build in code, written as plan YAML
// (`type: targets`, gdt/PLAN_FORMAT.md) and read back by the loader: the same frame.
std::string TargetsPlanYaml(const gdt::InspectionPlan& plan) {
  const gdt::DatumFrameSpec& f = *plan.datum_frame;
  auto sense = [](const gdt::AxisSense& s) -> std::string {
    switch (s.rule) {
      case gdt::AxisSense::Rule::kPointNormals: return "point_normals";
      case gdt::AxisSense::Rule::kAwayFrom: return "{away_from: " + s.feature + "}";
      case gdt::AxisSense::Rule::kToward: return "{toward: " + s.feature + "}";
      case gdt::AxisSense::Rule::kPointOrder: return "point_order";
    }
    return "";
  };
  std::string y = "schema: tpcal.inspection_plan/1\nname: targets\ndatum_frame:\n  type: targets\n";
  y += "  primary: " + f.primary + "\n  center: " + f.center + "\n";
  y += f.x_toward.empty() ? "  y_toward: " + f.y_toward + "\n" : "  x_toward: " + f.x_toward + "\n";
  if (f.toward_first_point) y += "  toward_first_point: true\n";
  y += "  z_sense: " + sense(f.z_sense) + "\nfeatures:\n";
  for (const auto& feature : plan.features)
    y += "  " + feature.name + ": {kind: " + gdt::FeatureKindName(feature.kind) + ", projection: " +
         gdt::ProjectionName(feature.projection) + "}\n";
  return y;
}

TEST(InspectionPlan, TargetsFramesReadBackFromPlanYaml) {
  FaceMillingPieceParams m2;
  ASSERT_GT(m2.passes, 1);  // the default M2 plan has a datum frame
  for (const PieceParams& p : std::vector<PieceParams>{m2, ConeFrustumParams{}}) {
    PieceConfig c;
    c.params = p;
    auto piece = MakeTestPiece(c, PlanAcTable());
    ASSERT_TRUE(piece.ok()) << piece.status().ToString();
    const auto& mine = piece->inspection.datum_frame;
    ASSERT_TRUE(mine.has_value());
    ASSERT_EQ(mine->type, gdt::DatumFrameType::kTargets);
    const std::string text = TargetsPlanYaml(piece->inspection);
    auto read = gdt::ParseInspectionPlan(text, piece->name + ".yaml");
    ASSERT_TRUE(read.ok()) << read.status().ToString() << "\n" << text;
    ASSERT_TRUE(read->datum_frame.has_value());
    const gdt::DatumFrameSpec& r = *read->datum_frame;
    EXPECT_EQ(r.type, gdt::DatumFrameType::kTargets) << piece->name;
    EXPECT_EQ(r.primary, mine->primary) << piece->name;
    EXPECT_EQ(r.center, mine->center) << piece->name;
    EXPECT_EQ(r.x_toward, mine->x_toward) << piece->name;
    EXPECT_EQ(r.y_toward, mine->y_toward) << piece->name;
    EXPECT_EQ(r.toward_first_point, mine->toward_first_point) << piece->name;
    EXPECT_EQ(r.z_sense.rule, mine->z_sense.rule) << piece->name;
    EXPECT_EQ(r.z_sense.feature, mine->z_sense.feature) << piece->name;
  }
}

TEST(InspectionPlan, TurningPlanAgreesWithTheGdtSamplePlan) {
  auto sample = gdt::LoadInspectionPlan(std::string(TPCAL_SOURCE_DIR) + "/samples/plans/turning.yaml");
  ASSERT_TRUE(sample.ok()) << sample.status().ToString();
  auto piece = MakeTestPiece(PieceConfig{}, PlanAcTable());
  ASSERT_TRUE(piece.ok());
  const gdt::InspectionPlan& mine = piece->inspection;

  ASSERT_TRUE(sample->datum_frame && mine.datum_frame);
  EXPECT_EQ(sample->datum_frame->type, mine.datum_frame->type);
  EXPECT_EQ(sample->datum_frame->primary, mine.datum_frame->primary);
  EXPECT_EQ(sample->datum_frame->center, mine.datum_frame->center);
  EXPECT_EQ(sample->datum_frame->x_toward, mine.datum_frame->x_toward);
  EXPECT_EQ(sample->datum_frame->z_sense.rule, mine.datum_frame->z_sense.rule);
  EXPECT_EQ(sample->datum_frame->z_sense.feature, mine.datum_frame->z_sense.feature);

  for (const gdt::PlanNominal& n : sample->nominals) {
    const auto v = mine.Nominal(n.name);
    ASSERT_TRUE(v.has_value()) << "nominal " << n.name << " of turning.yaml is not in the piece's plan";
    EXPECT_NEAR(*v, n.value, 1e-12) << n.name;
  }
  for (const gdt::FeatureSpec& f : sample->features) {
    const gdt::FeatureSpec* m = mine.FindFeature(f.name);
    ASSERT_NE(m, nullptr) << "feature " << f.name << " of turning.yaml is not in the piece's plan";
    EXPECT_EQ(m->kind, f.kind) << f.name;
    EXPECT_EQ(m->projection, f.projection) << f.name;
    EXPECT_EQ(m->members, f.members) << f.name;
  }
  for (const gdt::CharacteristicSpec& c : sample->characteristics) {
    const gdt::CharacteristicSpec* m = nullptr;
    for (const auto& x : mine.characteristics) {
      if (x.name == c.name) m = &x;
    }
    ASSERT_NE(m, nullptr) << "characteristic " << c.name << " of turning.yaml is not in the piece's plan";
    EXPECT_EQ(m->type, c.type) << c.name;
    EXPECT_EQ(m->feature, c.feature) << c.name;
    EXPECT_EQ(m->datum, c.datum) << c.name;
    EXPECT_EQ(m->nominal_radius_mm, c.nominal_radius_mm) << c.name;
    EXPECT_EQ(m->nominal_diameter_mm, c.nominal_diameter_mm) << c.name;
    EXPECT_EQ(m->first_angle_deg, c.first_angle_deg) << c.name;
    EXPECT_EQ(m->pitch_deg, c.pitch_deg) << c.name;
    // The nominal B3 - B_R distance follows from where B3 sits: the piece's parameters put the
    // probing circles at the paper's z_i (seed 002 sec. 3.2) and the shoulders 5 mm lower
    // (testpieces/README.md), i.e. -30 mm; turning.yaml must carry the same number.
    if (c.nominal_distance_mm || m->nominal_distance_mm) {
      ASSERT_TRUE(c.nominal_distance_mm && m->nominal_distance_mm) << c.name;
      EXPECT_NEAR(*m->nominal_distance_mm, *c.nominal_distance_mm, 1e-9)
          << c.name << ": turning.yaml nominal_distance_mm disagrees with the piece's geometry";
    }
  }
}

// The other direction: what the piece's plan holds beyond turning.yaml is only the bottom faces
// B2, B4, B5, B6 (the diagnosis uses them; the gdt sample keeps to Table 1), the characteristics
// on them and on other faces beyond Table 1, and more nominals. The Table 1 items are all there.
TEST(InspectionPlan, TurningPlanExtrasBeyondTheSampleAreOnlyBottomFacesAndDiagnosisItems) {
  auto sample = gdt::LoadInspectionPlan(std::string(TPCAL_SOURCE_DIR) + "/samples/plans/turning.yaml");
  ASSERT_TRUE(sample.ok()) << sample.status().ToString();
  auto piece = MakeTestPiece(PieceConfig{}, PlanAcTable());
  ASSERT_TRUE(piece.ok());
  std::set<std::string> extra_features;
  for (const auto& f : piece->inspection.features)
    if (sample->FindFeature(f.name) == nullptr) extra_features.insert(f.name);
  EXPECT_EQ(extra_features, (std::set<std::string>{"B2", "B4", "B5", "B6"}));
  std::set<std::string> sample_chars;
  for (const auto& c : sample->characteristics) sample_chars.insert(c.name);
  for (const char* t1 : {"t1_concentricity_Ch_SR", "t2_parallelism_B1_BR", "t3_distance_B3_BR", "t4_size_S3",
                         "t5_concentricity_S4_SR", "t6_concentricity_S4_S1", "t7_concentricity_S6_S3",
                         "ta_circularity_S1", "tb_circularity_S3", "tc_circularity_S4", "td_circularity_S6"})
    EXPECT_EQ(sample_chars.count(t1), 1u) << t1;
  for (const auto& c : piece->inspection.characteristics) {
    if (sample_chars.count(c.name)) continue;
    // Extras are never Table 1 items (those are named t1_ ... t7_, ta_ ... td_).
    const bool table1_name = c.name.size() > 2 && c.name[0] == 't' && c.name[2] == '_';
    EXPECT_FALSE(table1_name) << c.name;
  }
}

// The nominals the seed 002 equations use (heights from the A axis = part z, radii from the C
// axis) are where the probing plan actually probes: z_k on S_k, z_Bk and rho_Bk on B_k, z_h in
// the holes, z_R on B_R, r_SR on S_R, the hole centres on the pitch radius. Exact geometry.
TEST(InspectionPlan, TurningNominalsAreWhereThePlanProbes) {
  constexpr double kTol_mm = 1e-9;  // nominal points, double precision
  auto piece = MakeTestPiece(PieceConfig{}, PlanAcTable());
  ASSERT_TRUE(piece.ok());
  auto plan = MakeProbingPlan(*piece);
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  const gdt::InspectionPlan& ip = piece->inspection;
  const auto& params = std::get<TurningPieceParams>(piece->config.params);
  auto nominal = [&](const std::string& n) {
    const auto v = ip.Nominal(n);
    EXPECT_TRUE(v.has_value()) << n;
    return v.value_or(NAN);
  };
  auto radius = [](const Eigen::Vector3d& p) { return std::hypot(p.x(), p.y()); };
  std::set<std::string> seen;
  for (const PlanPoint& pt : plan->points) {
    const Eigen::Vector3d& p = pt.point_part_mm;
    const std::string& f = pt.feature;
    seen.insert(f);
    if (f == "B_R") {
      EXPECT_NEAR(p.z(), nominal("z_R_mm"), kTol_mm);
    } else if (f == "S_R") {
      EXPECT_NEAR(radius(p), nominal("r_SR_mm"), kTol_mm);
    } else if (f[0] == 'H') {
      EXPECT_NEAR(p.z(), nominal("z_h_mm"), kTol_mm) << f;
      // The hole wall point is the reamer radius from its centre on the pitch circle.
      const int k = std::stoi(f.substr(1));
      const double a = (k - 1) * nominal("hole_pitch_deg") * M_PI / 180.0;
      const Eigen::Vector3d centre(nominal("hole_pitch_radius_mm") * std::cos(a),
                                   nominal("hole_pitch_radius_mm") * std::sin(a), p.z());
      EXPECT_NEAR((p - centre).norm(), 0.5 * params.reamer_diameter_mm, kTol_mm) << f;
    } else if (f.size() == 2 && f[0] == 'S') {
      EXPECT_NEAR(p.z(), nominal("z" + f.substr(1) + "_mm"), kTol_mm) << f;
      EXPECT_NEAR(radius(p), nominal("r" + f.substr(1) + "_mm"), kTol_mm) << f;
    } else if (f.size() == 2 && f[0] == 'B') {
      EXPECT_NEAR(p.z(), nominal("z_B" + f.substr(1) + "_mm"), kTol_mm) << f;
      EXPECT_NEAR(radius(p), nominal("rho_B" + f.substr(1) + "_mm"), kTol_mm) << f;
    }
  }
  EXPECT_EQ(seen.count("H16"), 1u);
  EXPECT_EQ(seen.count("B6"), 1u);
  EXPECT_EQ(nominal("hole_count"), 16.0);
  // The S_R wall pass runs groove_wall_lift_mm above B_R (the z of the S_R cut, seed 002's z_R
  // of eqs. 10-11 for the holes-to-S_R relation).
  EXPECT_NEAR(nominal("z_SR_cut_mm") - nominal("z_R_mm"), 0.1, kTol_mm);
}

}  // namespace
}  // namespace tpcal::testpieces
