// End-to-end: the seed 002 turning test piece, built exactly in code with known errors, moved to
// random CMM placements, evaluated with samples/plans/turning.yaml. Truth is stated in the part
// frame P (B_R on z = 0, S_R centred on Z, holes nominally at 140 mm, H1 on +X) and carried into
// the datum frame D, which the measured features define (the shifted hole pattern turns D by phi
// about Z relative to P: D_from_P = RotZ(-phi)).
#include "gdt/inspection.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>

#include "core/units.h"
#include "gdt/form_zone.h"
#include "gdt/hole_pattern.h"
#include "gdt/plan_yaml.h"
#include "gdt/synthetic.h"
#include "gdt/testing/turning_piece.h"

namespace tpcal::gdt {
namespace {

using ::testing::HasSubstr;
using testing::HoleName;
using testing::kZ4;
using testing::MakeTurningPiece;
using testing::TurningTruth;

// Exact synthetic data: coordinates up to ~1300 mm after placement carry ~1e-13 mm of double
// rounding through transforms and fits. The bounds below (1 pm, 1 nrad) leave >1000x margin and
// are far below any CMM resolution, so a wrong sign or formula cannot hide under them.
constexpr double kInspectionTol_um = 1e-6;    // 1e-9 mm
constexpr double kInspectionTol_urad = 1e-3;  // 1e-9 rad
constexpr double kInspectionTol_mm = 1e-9;
constexpr double kTol_deg = 1e-7;   // profile angles: 1e-9 rad is 6e-8 deg
constexpr double kInspectionMaxTranslation_mm = 1000.0;

std::string SamplePlanPath() { return std::string(TPCAL_SOURCE_DIR) + "/samples/plans/turning.yaml"; }

// Theta (P frame) of the k-th point of a synthetic circle: 2 pi k / n.
double ThetaOfPoint(const PointSet& ps, std::size_t point_index, const std::string& feature) {
  const auto idx = ps.IndicesOf(feature);
  const auto it = std::find(idx.begin(), idx.end(), point_index);
  return 2 * kPi * static_cast<double>(it - idx.begin()) / static_cast<double>(idx.size());
}

InspectionPlan SamplePlan() {
  auto plan = LoadInspectionPlan(SamplePlanPath());
  EXPECT_TRUE(plan.ok()) << plan.status().ToString();
  return *plan;
}

double Get(const InspectionResult& r, const std::string& characteristic, const std::string& value) {
  const CharacteristicResult* c = r.Characteristic(characteristic);
  if (c == nullptr) {
    ADD_FAILURE() << "no characteristic " << characteristic;
    return std::nan("");
  }
  const auto v = c->Value(value);
  if (!v) {
    ADD_FAILURE() << characteristic << " has no value " << value;
    return std::nan("");
  }
  return *v;
}

class TurningPiece : public ::testing::Test {
 protected:
  Result<InspectionResult> Evaluate(const TurningTruth& truth, const Rigid3& cmm_from_part) {
    return EvaluatePlan(plan_, Transformed(MakeTurningPiece(truth), cmm_from_part));
  }
  InspectionPlan plan_ = SamplePlan();
};

// The brief's two headline cases, with an unshifted hole pattern (D = P exactly).
TEST_F(TurningPiece, SinglePerturbationsGiveTheirSignedValues) {
  TurningTruth t;
  t.holes_shift_mm.setZero();
  t.rotated_hole_rad = 0;
  t.s1_shift_mm.setZero();
  t.s3_shift_mm.setZero();
  t.s6_shift_mm.setZero();
  t.s4_shift_mm = {0.010, -0.005};  // S4 moved by (+10, -5) um in datum X / Y
  t.b1_about_x_rad = 8.7e-6;        // B1 tilted by +8.7 urad about datum X
  t.b1_about_y_rad = 0.0;
  std::mt19937_64 rng(1);
  auto r = Evaluate(t, RandomPlacement(rng, kInspectionMaxTranslation_mm));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_NEAR(Get(*r, "t5_concentricity_S4_SR", "dx_um"), 10.0, kInspectionTol_um);
  EXPECT_NEAR(Get(*r, "t5_concentricity_S4_SR", "dy_um"), -5.0, kInspectionTol_um);
  EXPECT_NEAR(Get(*r, "t5_concentricity_S4_SR", "zone_diameter_um"), 2 * std::hypot(10.0, 5.0), kInspectionTol_um);
  EXPECT_NEAR(Get(*r, "t6_concentricity_S4_S1", "dx_um"), 10.0, kInspectionTol_um);
  EXPECT_NEAR(Get(*r, "t2_parallelism_B1_BR", "da_urad"), 8.7, kInspectionTol_urad);
  EXPECT_NEAR(Get(*r, "t2_parallelism_B1_BR", "db_urad"), 0.0, kInspectionTol_urad);
  EXPECT_NEAR(Get(*r, "t1_concentricity_Ch_SR", "dx_um"), 0.0, kInspectionTol_um);
  EXPECT_NEAR(Get(*r, "t7_concentricity_S6_S3", "dy_um"), 0.0, kInspectionTol_um);
}

// All of Table 1 at the paper's magnitudes, from several CMM placements.
TEST_F(TurningPiece, Table1ItemsMatchTheKnownErrors) {
  const TurningTruth t;
  std::mt19937_64 rng(20240601);
  for (int trial = 0; trial < 3; ++trial) {
    SCOPED_TRACE(::testing::Message() << "placement " << trial);
    const Rigid3 cmm_from_part = RandomPlacement(rng, kInspectionMaxTranslation_mm);
    auto r = Evaluate(t, cmm_from_part);
    ASSERT_TRUE(r.ok()) << r.status().ToString();

    // The datum frame: D_from_cmm = RotZ(-phi) * P_from_cmm.
    const Rigid3 expected = MakeRigid(RotZ(-t.Phi()), Eigen::Vector3d::Zero()) * cmm_from_part.inverse();
    EXPECT_LT(Eigen::AngleAxisd(r->datum_from_cmm.linear().transpose() * expected.linear()).angle(), kInspectionTol_urad * 1e-6);
    EXPECT_LT((r->datum_from_cmm.translation() - expected.translation()).norm(), kInspectionTol_mm);

    // #1 (paper: 10.1, -17.2 um): the pitch centre, seen in D.
    const Eigen::Vector2d c1 = t.InD(t.holes_shift_mm) * kUmPerMm;
    EXPECT_NEAR(Get(*r, "t1_concentricity_Ch_SR", "dx_um"), c1.x(), kInspectionTol_um);
    EXPECT_NEAR(Get(*r, "t1_concentricity_Ch_SR", "dy_um"), c1.y(), kInspectionTol_um);
    // D is turned by phi = -123 urad: the paper's numbers hold to 0.01 um.
    EXPECT_NEAR(Get(*r, "t1_concentricity_Ch_SR", "dx_um"), 10.1, 0.01);
    EXPECT_NEAR(Get(*r, "t1_concentricity_Ch_SR", "dy_um"), -17.2, 0.01);

    // #2 (paper: -8.7, 1.7 urad): B1's normal n in D; da = atan2(-n_y, n_z), db = atan2(n_x, n_z).
    const Eigen::Vector3d n = RotZ(-t.Phi()) * RotX(t.b1_about_x_rad) * RotY(t.b1_about_y_rad) * Eigen::Vector3d::UnitZ();
    EXPECT_NEAR(Get(*r, "t2_parallelism_B1_BR", "da_urad"), RadToUrad(std::atan2(-n.y(), n.z())), kInspectionTol_urad);
    EXPECT_NEAR(Get(*r, "t2_parallelism_B1_BR", "db_urad"), RadToUrad(std::atan2(n.x(), n.z())), kInspectionTol_urad);
    EXPECT_NEAR(Get(*r, "t2_parallelism_B1_BR", "da_urad"), -8.7, 0.01);
    EXPECT_NEAR(Get(*r, "t2_parallelism_B1_BR", "db_urad"), 1.7, 0.01);
    // ISO zone: the spread along Z of B1's points (D shares P's Z axis).
    double z_lo = 1e9, z_hi = -1e9;
    const PointSet part = MakeTurningPiece(t);
    for (std::size_t i : part.IndicesOf("B1")) {
      z_lo = std::min(z_lo, part.xyz_mm[i].z());
      z_hi = std::max(z_hi, part.xyz_mm[i].z());
    }
    EXPECT_NEAR(Get(*r, "t2_parallelism_B1_BR", "zone_um"), MmToUm(z_hi - z_lo), kInspectionTol_um);

    // #3 (paper: 23.0 um) and #4 (paper: -14.5 um).
    // B3 moved up (+Z, toward B_R) by 23 um: error +23 um, separation (seed 002's dd) -23 um.
    EXPECT_NEAR(Get(*r, "t3_distance_B3_BR", "error_um"), 23.0, kInspectionTol_um);
    EXPECT_NEAR(Get(*r, "t3_distance_B3_BR", "separation_error_um"), -23.0, kInspectionTol_um);
    EXPECT_NEAR(Get(*r, "t3_distance_B3_BR", "distance_mm"), testing::kZB3 + 0.023, kInspectionTol_mm);
    EXPECT_NEAR(Get(*r, "t4_size_S3", "radius_error_um"), -14.5, kInspectionTol_um);
    EXPECT_NEAR(Get(*r, "t4_size_S3", "diameter_error_um"), -29.0, kInspectionTol_um);

    // #5, #6, #7.
    const Eigen::Vector2d c5 = t.InD(t.s4_shift_mm) * kUmPerMm;
    const Eigen::Vector2d c6 = t.InD(t.s4_shift_mm - t.s1_shift_mm) * kUmPerMm;
    const Eigen::Vector2d c7 = t.InD(t.s6_shift_mm - t.s3_shift_mm) * kUmPerMm;
    EXPECT_NEAR(Get(*r, "t5_concentricity_S4_SR", "dx_um"), c5.x(), kInspectionTol_um);
    EXPECT_NEAR(Get(*r, "t5_concentricity_S4_SR", "dy_um"), c5.y(), kInspectionTol_um);
    EXPECT_NEAR(Get(*r, "t6_concentricity_S4_S1", "dx_um"), c6.x(), kInspectionTol_um);
    EXPECT_NEAR(Get(*r, "t6_concentricity_S4_S1", "dy_um"), c6.y(), kInspectionTol_um);
    EXPECT_NEAR(Get(*r, "t7_concentricity_S6_S3", "dx_um"), c7.x(), kInspectionTol_um);
    EXPECT_NEAR(Get(*r, "t7_concentricity_S6_S3", "dy_um"), c7.y(), kInspectionTol_um);
    EXPECT_NEAR(c6.x(), -1.2, 0.01);
    EXPECT_NEAR(c6.y(), -0.7, 0.01);
    EXPECT_NEAR(c7.x(), -0.3, 0.01);
    EXPECT_NEAR(c7.y(), -2.2, 0.01);

    // Hole pattern: hole k's angle error is its own rotation minus phi (D is turned by phi).
    for (int k = 1; k <= 16; ++k) {
      const double expected_rad = (k == t.rotated_hole ? t.rotated_hole_rad : 0.0) - t.Phi();
      EXPECT_NEAR(Get(*r, "hole_pattern_Ch", HoleName(k) + ".angle_error_urad"), RadToUrad(expected_rad),
                  kInspectionTol_urad);
      EXPECT_NEAR(Get(*r, "hole_pattern_Ch", HoleName(k) + ".radial_error_um"), 0.0, kInspectionTol_um);
    }
    EXPECT_NEAR(Get(*r, "hole_pattern_Ch", "radius_error_um"), 0.0, kInspectionTol_um);
  }
}

// Profiles a-d (and S2, S5): dr at each point is the synthetic dr(theta_P); theta is reported in D.
TEST_F(TurningPiece, CircularityProfilesFollowTheDatumAngle) {
  const TurningTruth t;
  std::mt19937_64 rng(99);
  const PointSet part = MakeTurningPiece(t);
  auto r = EvaluatePlan(plan_, Transformed(part, RandomPlacement(rng, kInspectionMaxTranslation_mm)));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const std::pair<const char*, std::pair<const char*, std::function<double(double)>>> profiles[] = {
      {"ta_circularity_S1", {"S1", t.dr_s1}}, {"tb_circularity_S3", {"S3", t.dr_s3}},
      {"tc_circularity_S4", {"S4", t.dr_s4}}, {"td_circularity_S6", {"S6", t.dr_s6}},
      {"circularity_S2", {"S2", t.dr_s2}},    {"circularity_S5", {"S5", t.dr_s5}},
  };
  for (const auto& [name, feature_dr] : profiles) {
    SCOPED_TRACE(name);
    const auto& [feature, dr] = feature_dr;
    const CharacteristicResult* c = r->Characteristic(name);
    ASSERT_NE(c, nullptr);
    ASSERT_EQ(c->profile.size(), 16u);
    double lo = 1e9, hi = -1e9, previous_theta = -1;
    for (const ProfileSample& s : c->profile) {
      const double theta_p = ThetaOfPoint(part, s.point_index, feature);
      EXPECT_NEAR(s.dr_um, MmToUm(dr(theta_p)), kInspectionTol_um);
      double expected_deg = RadToDeg(WrapAngle(theta_p - t.Phi()));
      if (expected_deg < 0) expected_deg += 360.0;
      EXPECT_NEAR(s.theta_deg, expected_deg, kTol_deg);
      EXPECT_GT(s.theta_deg, previous_theta);  // sorted
      previous_theta = s.theta_deg;
      lo = std::min(lo, MmToUm(dr(theta_p)));
      hi = std::max(hi, MmToUm(dr(theta_p)));
    }
    EXPECT_NEAR(c->Value("circularity_um").value_or(-1), hi - lo, kInspectionTol_um);
    EXPECT_EQ(c->criterion, FormCriterion::kLeastSquares);
  }
}

// Every value of every characteristic is the same whatever the CMM placement.
TEST_F(TurningPiece, CharacteristicsDoNotDependOnThePlacement) {
  const TurningTruth t;
  std::mt19937_64 rng(5);
  auto first = Evaluate(t, RandomPlacement(rng, kInspectionMaxTranslation_mm));
  ASSERT_TRUE(first.ok()) << first.status().ToString();
  for (int trial = 0; trial < 3; ++trial) {
    auto other = Evaluate(t, RandomPlacement(rng, kInspectionMaxTranslation_mm));
    ASSERT_TRUE(other.ok());
    ASSERT_EQ(first->characteristics.size(), other->characteristics.size());
    for (std::size_t i = 0; i < first->characteristics.size(); ++i) {
      const auto& a = first->characteristics[i];
      const auto& b = other->characteristics[i];
      ASSERT_EQ(a.values.size(), b.values.size()) << a.name;
      for (std::size_t j = 0; j < a.values.size(); ++j) {
        const double tol = a.values[j].unit == "um" ? kInspectionTol_um : a.values[j].unit == "urad" ? kInspectionTol_urad : kInspectionTol_mm;
        EXPECT_NEAR(a.values[j].value, b.values[j].value, tol) << a.name << " " << a.values[j].name;
      }
    }
  }
}

TEST_F(TurningPiece, TooFewPointsCitesTheFirstPointOfTheFeature) {
  TurningTruth t;
  t.h3_points = 2;
  std::mt19937_64 rng(3);
  const PointSet ps = Transformed(MakeTurningPiece(t), RandomPlacement(rng, kInspectionMaxTranslation_mm));
  auto r = EvaluatePlan(plan_, ps);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kTooFewPoints);
  EXPECT_EQ(r.status().file(), "synthetic turning piece");
  // Data rows start on line 4: B_R (16), S_R (16), H1 (8), H2 (8), then H3.
  EXPECT_EQ(r.status().line(), 4u + 16 + 16 + 8 + 8);
  EXPECT_EQ(r.status().line(), ps.line[ps.IndicesOf("H3").front()]);
  EXPECT_THAT(r.status().message(), HasSubstr("'H3'"));
  EXPECT_THAT(r.status().message(), HasSubstr("2 points"));
}

TEST_F(TurningPiece, AMissingFeatureCitesThePlanLine) {
  TurningTruth t;
  t.with_s6 = false;
  auto r = Evaluate(t, Rigid3::Identity());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().file(), SamplePlanPath());
  EXPECT_EQ(r.status().line(), plan_.FindFeature("S6")->line);
  EXPECT_THAT(r.status().message(), HasSubstr("'S6' has no points"));
}

TEST_F(TurningPiece, MinimumZoneCircularityComesFromTheFittingLayer) {
  if (!MinimumZoneAvailable()) GTEST_SKIP() << "fitting/minimum_zone.h not in this build";
  // S2's profile 1 um cos(4 theta) on 16 points has 8 alternating contacts at its LS centre:
  // the minimum zone equals the LS range, 2 um.
  InspectionPlan plan = plan_;
  for (auto& c : plan.characteristics)
    if (c.name == "circularity_S2") c.criterion = FormCriterion::kMinimumZone;
  auto r = EvaluatePlan(plan, Transformed(MakeTurningPiece(TurningTruth{}), Rigid3::Identity()));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_NEAR(Get(*r, "circularity_S2", "circularity_um"), 2.0, kInspectionTol_um);
  EXPECT_NEAR(Get(*r, "circularity_S2", "mz_um"), 2.0, kInspectionTol_um);
  EXPECT_NEAR(Get(*r, "circularity_S2", "ls_um"), 2.0, kInspectionTol_um);
  // S1's two harmonics: the minimum zone can only be narrower than the LS range.
  for (auto& c : plan.characteristics)
    if (c.name == "ta_circularity_S1") c.criterion = FormCriterion::kMinimumZone;
  r = EvaluatePlan(plan, Transformed(MakeTurningPiece(TurningTruth{}), Rigid3::Identity()));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_LE(Get(*r, "ta_circularity_S1", "mz_um"), Get(*r, "ta_circularity_S1", "ls_um") + kInspectionTol_um);
  EXPECT_GT(Get(*r, "ta_circularity_S1", "mz_um"), 0.0);
}

TEST_F(TurningPiece, FittedFeaturesAreReportedInTheDatumFrame) {
  const TurningTruth t;
  std::mt19937_64 rng(11);
  auto r = Evaluate(t, RandomPlacement(rng, kInspectionMaxTranslation_mm));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const FittedFeature* s_r = r->Feature("S_R");
  ASSERT_NE(s_r, nullptr);
  const auto* c = s_r->As<fitting::Circle2>();
  ASSERT_NE(c, nullptr);
  EXPECT_LT(c->feature.center_mm.norm(), kInspectionTol_mm);  // the origin, by construction
  EXPECT_NEAR(c->feature.radius_mm, testing::kRSR, kInspectionTol_mm);
  EXPECT_NEAR(s_r->height_mm, testing::kZSR, kInspectionTol_mm);
  const FittedFeature* b_r = r->Feature("B_R");
  ASSERT_NE(b_r->As<fitting::Plane>(), nullptr);
  EXPECT_LT((b_r->As<fitting::Plane>()->feature.normal - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
  const FittedFeature* ch = r->Feature("C_h");
  ASSERT_NE(ch, nullptr);
  EXPECT_EQ(ch->kind, FeatureKind::kPitchCircle);
  EXPECT_EQ(ch->members.size(), 16u);
  ASSERT_TRUE(r->Feature("S1")->form_mm().has_value());
  EXPECT_NEAR(MmToUm(*r->Feature("S4")->form_mm()), 1.0, kInspectionTol_um);  // 0.5 um cos(2 theta): range 1 um
}

TEST(EvaluateAdHoc, FitsEveryLabelledFeatureWithKindsFromNormals) {
  const TurningTruth t;
  std::mt19937_64 rng(17);
  const Rigid3 cmm_from_part = RandomPlacement(rng, kInspectionMaxTranslation_mm);
  const PointSet ps = Transformed(MakeTurningPiece(t), cmm_from_part);
  auto r = EvaluateAdHoc(ps, {});
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->features.size(), ps.feature_names.size());
  EXPECT_FALSE(r->frame_type.has_value());
  EXPECT_EQ(r->Feature("B1")->kind, FeatureKind::kPlane);
  EXPECT_EQ(r->Feature("H7")->kind, FeatureKind::kCircle);
  // No datum frame: a 3D circle in the CMM frame.
  const auto* s4 = r->Feature("S4")->As<fitting::Circle3>();
  ASSERT_NE(s4, nullptr);
  const Eigen::Vector3d expected = cmm_from_part * Eigen::Vector3d(t.s4_shift_mm.x(), t.s4_shift_mm.y(), kZ4);
  EXPECT_LT((s4->feature.center_mm - expected).norm(), kInspectionTol_mm);
}

TEST(EvaluateAdHoc, WithoutNormalsEveryKindMustBeGiven) {
  PointSet ps = MakeTurningPiece(TurningTruth{});
  ps.normal.clear();
  auto r = EvaluateAdHoc(ps, {});
  ASSERT_FALSE(r.ok());
  EXPECT_THAT(r.status().message(), HasSubstr("no normals"));
  AdHocOptions options;
  for (const auto& name : ps.feature_names)
    options.kinds[name] = name[0] == 'B' ? FeatureKind::kPlane : FeatureKind::kCircle;
  r = EvaluateAdHoc(ps, options);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  options.kinds["NOPE"] = FeatureKind::kPlane;
  EXPECT_THAT(EvaluateAdHoc(ps, options).status().message(), HasSubstr("'NOPE'"));
}

// A block measured with a 3-2-1 frame: primary face (z = 0), secondary line along its front
// edge face (y = 0), tertiary point on its left face (x = 0); a side face perpendicular to the
// primary with a known squareness error; a hole with a known position error.
TEST(ThreeTwoOnePlan, FrameSquarenessAndPosition) {
  const char* const text =
      "schema: tpcal.inspection_plan/1\n"
      "datum_frame:\n"
      "  type: 3-2-1\n"
      "  primary: A\n"
      "  secondary: B\n"
      "  tertiary: C\n"
      "  z_sense: {away_from: BODY}\n"
      "  x_sense: point_order\n"
      "features:\n"
      "  A: {kind: plane}\n"
      "  B: {kind: line3}\n"
      "  C: {kind: point}\n"
      "  BODY: {kind: point}\n"
      "  SIDE: {kind: plane, nominal_direction: [1, 0, 0]}\n"
      "  HOLE: {kind: circle}\n"
      "characteristics:\n"
      "  - {name: sq, type: squareness, feature: SIDE, datum: A}\n"
      "  - {name: pos, type: position, feature: HOLE, nominal_xy_mm: [60, 40]}\n"
      "  - {name: flat, type: flatness, feature: A}\n";
  auto plan = ParseInspectionPlan(text, "block.yaml");
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();

  const double d = 12e-6;  // SIDE leans so its outward normal tips toward +Z: angle < 90 deg
  PointSet part;
  part.source = "block";
  AppendPlaneRing(&part, "A", {.center_mm = {50, 50, 0}, .radius_mm = 40.0});
  for (int i = 0; i <= 10; ++i) {  // B: along +X at y = 0, z = 5 (probe order = +X)
    part.xyz_mm.emplace_back(10.0 * i, 0.0, 5.0);
    part.feature.push_back(part.InternFeature("B"));
    part.line.push_back(part.line.back() + 1);
  }
  part.xyz_mm.emplace_back(0.0, 30.0, 4.0);  // C on x = 0
  part.feature.push_back(part.InternFeature("C"));
  part.line.push_back(part.line.back() + 1);
  part.xyz_mm.emplace_back(50.0, 50.0, -40.0);  // BODY: the part lies below A
  part.feature.push_back(part.InternFeature("BODY"));
  part.line.push_back(part.line.back() + 1);
  for (double z : {-5.0, -25.0})
    for (double y : {10.0, 50.0, 90.0}) {
      part.xyz_mm.push_back(Eigen::Vector3d(100, 0, 0) + RotY(-d) * Eigen::Vector3d(0, y, z));
      part.feature.push_back(part.InternFeature("SIDE"));
      part.line.push_back(part.line.back() + 1);
    }
  AppendCircle(&part, "HOLE", {.center_mm = {60.004, 39.997, -2}, .radius_mm = 4.0, .n_points = 8, .hole = true});
  part.normal.clear();

  std::mt19937_64 rng(8);
  auto r = EvaluatePlan(*plan, Transformed(part, RandomPlacement(rng, kInspectionMaxTranslation_mm)));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_NEAR(Get(*r, "sq", "angle_urad"), 12.0, kInspectionTol_urad);
  EXPECT_NEAR(Get(*r, "sq", "zone_um"), MmToUm(20.0 * std::sin(d)), kInspectionTol_um);
  EXPECT_NEAR(Get(*r, "pos", "dx_um"), 4.0, kInspectionTol_um);
  EXPECT_NEAR(Get(*r, "pos", "dy_um"), -3.0, kInspectionTol_um);
  EXPECT_NEAR(Get(*r, "pos", "position_diameter_um"), 10.0, kInspectionTol_um);
  EXPECT_NEAR(Get(*r, "flat", "flatness_um"), 0.0, kInspectionTol_um);
}

}  // namespace
}  // namespace tpcal::gdt

namespace tpcal::gdt {
namespace {

// Form characteristics whose minimum-zone values are known in closed form.
TEST(FormCharacteristics, LeastSquaresAndMinimumZoneValues) {
  if (!MinimumZoneAvailable()) GTEST_SKIP() << "fitting/minimum_zone.h not in this build";
  InspectionPlan plan;
  plan.source = "form plan";
  plan.features = {{.name = "P", .kind = FeatureKind::kPlane, .form_criterion = FormCriterion::kMinimumZone},
                   {.name = "L", .kind = FeatureKind::kLine2, .projection = Projection::kDatumXY}};
  plan.characteristics = {
      {.name = "flat", .type = CharacteristicType::kFlatness, .feature = "P"},
      {.name = "straight", .type = CharacteristicType::kStraightness, .feature = "L",
       .criterion = FormCriterion::kMinimumZone},
  };
  PointSet ps;
  ps.source = "form points";
  // Plane ring with dz = A cos(2 theta): 4 points at +A, 4 at -A placed symmetrically: no tilt
  // narrows the zone, LS and MZ are both 2 A.
  const double a = 0.0015;
  AppendPlaneRing(&ps, "P", {.radius_mm = 50.0, .dz_mm = [a](double t) { return a * std::cos(2 * t); }});
  // Line points (0,0) (1,h) (2,0) (3,h): MZ strip width h (horizontal lines), LS line slope h/5
  // leaves residuals -0.2h, 0.6h, -0.6h, 0.2h: LS range 1.2 h.
  const double h = 0.001;
  for (int i = 0; i < 4; ++i) {
    ps.xyz_mm.emplace_back(10.0 * i, i % 2 == 1 ? h : 0.0, 7.0);
    ps.normal.push_back(Eigen::Vector3d::UnitY());
    ps.feature.push_back(ps.InternFeature("L"));
    ps.line.push_back(ps.line.back() + 1);
  }
  // Line spacing 10 mm: slope h/50; the scaled values are h (MZ) and 1.2 h cos(atan(h/50)).
  auto r = EvaluatePlan(plan, ps);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_NEAR(Get(*r, "flat", "flatness_um"), MmToUm(2 * a), kInspectionTol_um);  // the feature's criterion: mz
  EXPECT_NEAR(Get(*r, "flat", "ls_um"), MmToUm(2 * a), kInspectionTol_um);
  EXPECT_NEAR(MmToUm(*r->Feature("P")->form_mm()), MmToUm(2 * a), kInspectionTol_um);
  EXPECT_NEAR(Get(*r, "straight", "straightness_um"), MmToUm(h), kInspectionTol_um);
  EXPECT_NEAR(Get(*r, "straight", "ls_um"), MmToUm(1.2 * h * std::cos(std::atan(h / 50))), kInspectionTol_um);
}

}  // namespace
}  // namespace tpcal::gdt
