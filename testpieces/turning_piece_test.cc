// The seed 002 turning piece: machine states of section 2.1, cut-state association consistency,
// time stamps, validation of machinability.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "core/units.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/simulate.h"
#include "testpieces/probing_plan.h"
#include "testpieces/test_piece.h"

namespace tpcal::testpieces {
namespace {

constexpr double kExact_mm = 1e-9;  // double-precision planning identities

kinematics::MachineModel TurningAcTable() {
  auto m = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  EXPECT_TRUE(m.ok());
  return *m;
}

TestPiece TurningPieceUnderTest(const TurningPieceParams& p = {}) {
  PieceConfig config;
  config.params = p;
  auto piece = MakeTestPiece(config, TurningAcTable());
  EXPECT_TRUE(piece.ok()) << piece.status().ToString();
  return *piece;
}

const PlanPoint& First(const ProbingPlan& plan, const std::string& feature) {
  for (const auto& p : plan.points) {
    if (p.feature == feature) return p;
  }
  ADD_FAILURE() << "no point of " << feature;
  return plan.points.front();
}

TEST(TurningPiece, FeaturesAndOperationsFollowThePaper) {
  const TestPiece piece = TurningPieceUnderTest();
  ASSERT_EQ(piece.features.size(), 2u + 16u + 12u);
  EXPECT_EQ(piece.features[0].name, "S_R");
  EXPECT_EQ(piece.features[1].name, "B_R");
  EXPECT_EQ(piece.features[2].name, "H1");
  EXPECT_EQ(piece.features.back().name, "B6");
  ASSERT_EQ(piece.operations.size(), 8u);
  const char* names[8] = {"groove", "holes", "turn S1/B1", "turn S4/B4", "turn S2/B2", "turn S5/B5", "turn S3/B3",
                          "turn S6/B6"};
  for (int i = 0; i < 8; ++i) {
    EXPECT_EQ(piece.operations[i].name, names[i]);
    EXPECT_EQ(piece.operations[i].number, i + 1);
    if (i > 0) {
      EXPECT_GE(piece.operations[i].start_time_s, piece.operations[i - 1].end_time_s - 1e-9);
    }
  }
  // Datum frame: B_R at z = 0.
  EXPECT_NEAR(piece.part_from_datum.translation().z(), 405.702, 1e-12);
  // The whole program takes tens of minutes (reaming at 9.6 mm/min dominates).
  EXPECT_GT(piece.duration_s(), 1800.0);
  EXPECT_LT(piece.duration_s(), 4 * 3600.0);
}

TEST(TurningPiece, MachineStatesOfSection21) {
  const TestPiece piece = TurningPieceUnderTest();
  auto plan = MakeProbingPlan(piece);
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  const double rn = 0.8;
  // Holes: every hole at machine (140, 0), C = 22.5 (k - 1) deg, A = 0.
  for (int k = 1; k <= 16; ++k) {
    for (const auto& p : plan->points) {
      if (p.feature != "H" + std::to_string(k)) {
        continue;
      }
      EXPECT_NEAR(p.cut.axes.x_mm, 140.0, kExact_mm);
      EXPECT_NEAR(p.cut.axes.y_mm, 0.0, kExact_mm);
      EXPECT_NEAR(RadToDeg(p.cut.axes.c_rad), 22.5 * (k - 1), 1e-9);
      EXPECT_EQ(p.cut.axes.a_rad, 0.0);
      EXPECT_EQ(p.cut.axes.op, 2);
      // Tip at the probing height (z_h = 410.702 - 7.5).
      EXPECT_NEAR(p.cut.axes.z_mm, 403.202, kExact_mm);
    }
  }
  // S1: A = 0, tool at +X (Y = 0), nose centre at r1 + rn, feed -Z; B1 feed -X.
  const PlanPoint& s1 = First(*plan, "S1");
  EXPECT_EQ(s1.cut.axes.a_rad, 0.0);
  EXPECT_NEAR(s1.cut.axes.x_mm, 160.0 + rn, kExact_mm);
  EXPECT_NEAR(s1.cut.axes.y_mm, 0.0, kExact_mm);
  EXPECT_NEAR(s1.cut.axes.z_mm, 400.702, kExact_mm);
  EXPECT_LT(s1.cut.du.axes.z_mm, -0.999);
  const PlanPoint& b1 = First(*plan, "B1");
  EXPECT_LT(b1.cut.du.axes.x_mm, -0.999);
  // S2: A = 0, X = 0, tool at +Y; B2 by -Y feed.
  const PlanPoint& s2 = First(*plan, "S2");
  EXPECT_NEAR(s2.cut.axes.x_mm, 0.0, kExact_mm);
  EXPECT_NEAR(s2.cut.axes.y_mm, 165.0 + rn, kExact_mm);
  EXPECT_LT(s2.cut.du.axes.z_mm, -0.999);
  EXPECT_LT(First(*plan, "B2").cut.du.axes.y_mm, -0.999);
  // S3: A = -90, X = 0, tool above the part at Z = r3 + rn, machine Y = -z3; S3 by +Y feed,
  // B3 by -Z feed (seed 002 step 7).
  const PlanPoint& s3 = First(*plan, "S3");
  EXPECT_NEAR(RadToDeg(s3.cut.axes.a_rad), -90.0, 1e-12);
  EXPECT_NEAR(s3.cut.axes.x_mm, 0.0, kExact_mm);
  EXPECT_NEAR(s3.cut.axes.z_mm, 170.0 + rn, kExact_mm);
  EXPECT_NEAR(s3.cut.axes.y_mm, -380.702, kExact_mm);
  EXPECT_GT(s3.cut.du.axes.y_mm, 0.999);
  EXPECT_LT(First(*plan, "B3").cut.du.axes.z_mm, -0.999);
  // The groove: A = C = 0, tool on the circle of S_R - 4 mm.
  const PlanPoint& sr = First(*plan, "S_R");
  EXPECT_EQ(sr.cut.axes.a_rad, 0.0);
  EXPECT_EQ(sr.cut.axes.c_rad, 0.0);
  EXPECT_NEAR(std::hypot(sr.cut.axes.x_mm, sr.cut.axes.y_mm), 119.0 - 4.0, kExact_mm);
  EXPECT_EQ(sr.cut.axes.op, 1);
}

TEST(TurningPiece, EveryPlanPointIsItsOwnCutPoint) {
  const kinematics::MachineModel m = TurningAcTable();
  for (const ProbingOptions& density : {ProbingOptions::Paper(), ProbingOptions::Dense()}) {
    const TestPiece piece = TurningPieceUnderTest();
    auto plan = MakeProbingPlan(piece, density);
    ASSERT_TRUE(plan.ok()) << plan.status().ToString();
    for (const PlanPoint& p : plan->points) {
      // Nominal machine: the tool point at the cut state is the plan point itself.
      EXPECT_LT(kinematics::CutPointMismatch(m, p.cut), kExact_mm) << p.feature;
      EXPECT_NEAR(p.cut.nominal_normal.norm(), 1.0, 1e-12);
      EXPECT_GT(p.cut.axes.t_s, 0.0);
    }
  }
}

TEST(TurningPiece, CountsOfThePaperPlanAndTheDenseOne) {
  const TestPiece piece = TurningPieceUnderTest();
  auto paper = MakeProbingPlan(piece);
  ASSERT_TRUE(paper.ok());
  std::map<std::string, int> count;
  for (const auto& p : paper->points) ++count[p.feature];
  EXPECT_EQ(count["S1"], 16);
  EXPECT_EQ(count["B6"], 16);
  EXPECT_EQ(count["S_R"], 16);
  EXPECT_EQ(count["H7"], 8);
  auto dense = MakeProbingPlan(piece, ProbingOptions::Dense());
  ASSERT_TRUE(dense.ok());
  count.clear();
  for (const auto& p : dense->points) ++count[p.feature];
  EXPECT_EQ(count["S4"], 64 * 5);
  EXPECT_EQ(count["H1"], 16 * 3);
}

TEST(TurningPiece, PlanSizeIsCountedAndBoundedBeforeAnyPointIsMade) {
  const TestPiece piece = TurningPieceUnderTest();
  for (const ProbingOptions& density : {ProbingOptions::Paper(), ProbingOptions::Dense()}) {
    auto plan = MakeProbingPlan(piece, density);
    ASSERT_TRUE(plan.ok());
    EXPECT_EQ(PlannedPointCount(piece, density), static_cast<std::int64_t>(plan->points.size()));
  }
  ProbingOptions huge;
  huge.points_per_circle = 1'000'000'000;
  huge.levels_per_face = 1'000'000'000;  // 10^18 per face: counted without overflow
  EXPECT_GT(PlannedPointCount(piece, huge), kMaxPlanPoints);
  huge.grid_per_side = 2'000'000'000;
  EXPECT_GT(PlannedPointCount(piece, huge), kMaxPlanPoints);
  auto refused = MakeProbingPlan(piece, huge);  // returns at once: nothing allocated
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(refused.status().message().find("expected at most 3000000"), std::string::npos)
      << refused.status().message();
}

TEST(TurningPiece, AssociationOfMeasuredPointsNearAFeature) {
  const TestPiece piece = TurningPieceUnderTest();
  auto plan = MakeProbingPlan(piece);
  ASSERT_TRUE(plan.ok());
  for (const PlanPoint& p : plan->points) {
    // A measured point 7 um off the surface: same nominal point, same state.
    const Eigen::Vector3d measured = p.point_part_mm + 0.007 * p.normal_part;
    auto cut = CutPointAt(piece, p.feature, measured);
    ASSERT_TRUE(cut.ok()) << p.feature << ": " << cut.status().ToString();
    EXPECT_LT((cut->nominal_point_mm - p.point_part_mm).norm(), 1e-9);
    EXPECT_NEAR(cut->axes.t_s, p.cut.axes.t_s, 1e-9);
    EXPECT_NEAR(cut->axes.c_rad, p.cut.axes.c_rad, 1e-12);
    // The datum-frame form gives the same.
    auto via_datum = CutPointAtDatum(piece, p.feature, piece.part_from_datum.inverse() * measured);
    ASSERT_TRUE(via_datum.ok());
    EXPECT_NEAR(via_datum->axes.z_mm, cut->axes.z_mm, 1e-9);
  }
}

TEST(TurningPiece, AzimuthMapsToCAndHeightToTime) {
  const TestPiece piece = TurningPieceUnderTest();
  // S4 at A = 0, tool at +X: a point at azimuth phi was cut at C = phi.
  for (double phi_deg : {10.0, 100.0, 250.0}) {
    const double phi = DegToRad(phi_deg);
    auto cut = CutPointAt(piece, "S4", Eigen::Vector3d(175 * std::cos(phi), 175 * std::sin(phi), 200.0));
    ASSERT_TRUE(cut.ok());
    EXPECT_NEAR(RadToDeg(cut->axes.c_rad), phi_deg, 1e-9);
    // S5 (tool at +Y): C = phi - 90.
    auto c5 = CutPointAt(piece, "S5", Eigen::Vector3d(180 * std::cos(phi), 180 * std::sin(phi), 150.0));
    ASSERT_TRUE(c5.ok());
    EXPECT_NEAR(RadToDeg(c5->axes.c_rad), std::fmod(phi_deg - 90.0 + 360.0, 360.0), 1e-9);
    // S6 (A = -90, tool above = part +Y at C = 0): C = phi - 90.
    auto c6 = CutPointAt(piece, "S6", Eigen::Vector3d(185 * std::cos(phi), 185 * std::sin(phi), 140.0));
    ASSERT_TRUE(c6.ok());
    EXPECT_NEAR(RadToDeg(c6->axes.c_rad), std::fmod(phi_deg - 90.0 + 360.0, 360.0), 1e-9);
  }
  // The S4 pass feeds down: lower points are cut later, at 0.2 mm/rev and 250 m/min
  // (227.4 rpm at r = 175: 45.47 mm/min).
  auto high = CutPointAt(piece, "S4", Eigen::Vector3d(175, 0, 300.0));
  auto low = CutPointAt(piece, "S4", Eigen::Vector3d(175, 0, 200.0));
  ASSERT_TRUE(high.ok() && low.ok());
  const double rpm = 250000.0 / (2 * kPi * 175.0);
  EXPECT_NEAR(low->axes.t_s - high->axes.t_s, 100.0 / (0.2 * rpm) * 60.0, 1e-6);
  // Operation order: S4 (op 4) before S2 (op 5).
  auto s2 = CutPointAt(piece, "S2", Eigen::Vector3d(165, 0, 390.0));
  ASSERT_TRUE(s2.ok());
  EXPECT_GT(s2->axes.t_s, low->axes.t_s);
  EXPECT_EQ(s2->axes.op, 5);
}

TEST(TurningPiece, PointsAwayFromAFeatureAreRejected) {
  const TestPiece piece = TurningPieceUnderTest();
  // Below the shoulder of S1 (not reached by the S1 feed).
  EXPECT_FALSE(CutPointAt(piece, "S1", Eigen::Vector3d(160, 0, 380.0)).ok());
  // On the axis of a turned face.
  EXPECT_FALSE(CutPointAt(piece, "S1", Eigen::Vector3d(0, 0, 400.0)).ok());
  // Unknown feature.
  EXPECT_FALSE(CutPointAt(piece, "S9", Eigen::Vector3d(160, 0, 400.0)).ok());
  // B_R outside the flat end of the floor passes (inside the inner corner radius region).
  EXPECT_FALSE(CutPointAt(piece, "B_R", Eigen::Vector3d(109.2, 0, 405.702)).ok());
}

TEST(TurningPiece, InnerWallEnrichmentAddsAClockwiseReferenceCircle) {
  TurningPieceParams p;
  p.groove_inner_wall_pass = true;
  const TestPiece piece = TurningPieceUnderTest(p);
  ASSERT_NE(piece.Feature("S_RI"), nullptr);
  ASSERT_EQ(piece.operations[0].passes.size(), 3u);
  const auto* cut = std::get_if<PathMillCut>(&piece.Cut("S_RI")->model);
  ASSERT_NE(cut, nullptr);
  EXPECT_TRUE(cut->elements[0].clockwise);
  const auto* outer = std::get_if<PathMillCut>(&piece.Cut("S_R")->model);
  EXPECT_FALSE(outer->elements[0].clockwise);
  auto c = CutPointAt(piece, "S_RI", Eigen::Vector3d(0, 109, 408.0));
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  EXPECT_NEAR(std::hypot(c->axes.x_mm, c->axes.y_mm), 113.0, kExact_mm);
  // The plan gains the inner-wall characteristics.
  EXPECT_NE(piece.inspection.FindFeature("S_RI"), nullptr);
}

TEST(TurningPiece, UnmachinableGeometryIsRejected) {
  // S4 with the radius of S1 (160 mm) under S3 (170 mm): an A = 0 tool cannot reach it.
  TurningPieceParams p;
  p.steps[3].radius_mm = 160.0;
  Status s = p.Validate();
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("steps[3].radius_mm"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("would hit S3"), std::string::npos) << s.message();
  // A finishing stock so large that S1 with its stock reaches the path of the tool turning S2.
  TurningPieceParams d;
  d.turning_depth_of_cut_mm = 5.0;
  s = d.Validate();
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("reaching S2 would hit S1"), std::string::npos) << s.message();
  // A turning holder too short for B5 (265 mm below the top).
  TurningPieceParams q;
  q.turning_tool_reach_mm = 200.0;
  s = q.Validate();
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("turning_tool.reach_mm"), std::string::npos) << s.message();
  // Holes into the groove.
  TurningPieceParams r;
  r.groove_outer_radius_mm = 136.0;
  EXPECT_FALSE(r.Validate().ok());
  // Probing height on the nose fillet.
  TurningPieceParams t;
  t.steps[0].probe_z_mm = t.steps[0].shoulder_z_mm + 0.5;
  EXPECT_FALSE(t.Validate().ok());
  // Not an A/C machine.
  PieceConfig config;
  auto xyz = kinematics::MakeMachine(kinematics::MachineType::kXyz);
  ASSERT_TRUE(xyz.ok());
  EXPECT_FALSE(MakeTestPiece(config, *xyz).ok());
}

TEST(TurningPiece, PlanRowsCarryTheContractColumns) {
  const TestPiece piece = TurningPieceUnderTest();
  auto plan = MakeProbingPlan(piece);
  ASSERT_TRUE(plan.ok());
  const auto cols = PlanExtraColumns(piece.machine);
  const std::vector<std::string> expected = {"op", "t_s", "A_deg", "C_deg", "X_mm", "Y_mm", "Z_mm"};
  EXPECT_EQ(cols, expected);
  const auto rows = PlanRows(*plan);
  ASSERT_EQ(rows.size(), plan->points.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    const auto& p = plan->points[i];
    // Datum frame: B_R at z = 0.
    EXPECT_NEAR(r.xyz_mm.z(), p.point_part_mm.z() - 405.702, 1e-9);
    EXPECT_EQ(r.op, p.cut.axes.op);
    EXPECT_NEAR(r.x_mm, p.cut.axes.x_mm, 0.0);
    EXPECT_NEAR(r.a_deg, RadToDeg(p.cut.axes.a_rad), 0.0);
    if (r.feature == "B_R") {
      EXPECT_NEAR(r.xyz_mm.z(), 0.0, 1e-9);
    }
    if (r.feature == "S3") {
      EXPECT_NEAR(r.a_deg, -90.0, 1e-12);
    }
  }
  const PointSet ps = PlanPointSet(*plan);
  EXPECT_EQ(ps.size(), rows.size());
  EXPECT_TRUE(ps.has_normals());
}

}  // namespace
}  // namespace tpcal::testpieces
