// ISO 10791-7 M1 (both sizes), M2 and the cone frustum: build, plan consistency, GD&T of the
// virtually machined piece, and the sweep directions of every cut point (exact vs first order).
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "core/units.h"
#include "gdt/inspection.h"
#include "kinematics/errors_yaml.h"
#include "kinematics/forward_kinematics.h"
#include "testpieces/simulate_piece.h"

namespace tpcal::testpieces {
namespace {

kinematics::MachineModel Machine(kinematics::MachineType t) {
  auto m = kinematics::MakeMachine(t);
  EXPECT_TRUE(m.ok());
  return *m;
}

TestPiece MakeIsoPiece(const PieceParams& params, const kinematics::MachineModel& m) {
  PieceConfig c;
  c.params = params;
  auto p = MakeTestPiece(c, m);
  EXPECT_TRUE(p.ok()) << p.status().ToString();
  return *p;
}

gdt::InspectionResult EvaluateIso(const TestPiece& piece, const kinematics::MachineModel& m,
                               const kinematics::ErrorState& e, bool random_placement) {
  PieceSimOptions o;
  o.random_placement = random_placement;
  o.seed = 11;
  auto sim = SimulatePiece(piece, m, e, o);
  EXPECT_TRUE(sim.ok()) << sim.status().ToString();
  auto r = gdt::EvaluatePlan(piece.inspection, sim->points);
  EXPECT_TRUE(r.ok()) << r.status().ToString();
  return *r;
}

double IsoValue(const gdt::InspectionResult& r, const std::string& c, const std::string& v) {
  const auto* ch = r.Characteristic(c);
  EXPECT_NE(ch, nullptr) << c;
  return ch ? ch->Value(v).value_or(NAN) : NAN;
}

TEST(IsoPieces, M1BothSizesOnThreeAxisAndFiveAxisMachines) {
  for (double size : {160.0, 320.0}) {
    for (auto type : {kinematics::MachineType::kXyz, kinematics::MachineType::kAcTable}) {
      const auto m = Machine(type);
      const TestPiece piece = MakeIsoPiece(ContourPieceParams::ForSize(size), m);
      EXPECT_EQ(piece.features.size(), 1u + 4u + 4u + 1u + 4u + 1u);
      EXPECT_EQ(piece.operations.size(), 5u);
      auto plan = MakeProbingPlan(piece);
      ASSERT_TRUE(plan.ok()) << plan.status().ToString();
      for (const auto& p : plan->points) EXPECT_LT(kinematics::CutPointMismatch(m, p.cut), 1e-9) << p.feature;
      // Zero errors: nominal GD&T.
      const auto r = EvaluateIso(piece, m, kinematics::ErrorState(m), true);
      EXPECT_NEAR(IsoValue(r, "straightness_SQ_XP", "straightness_um"), 0.0, 1e-6);
      EXPECT_NEAR(IsoValue(r, "squareness_SQ_XP_SQ_YN", "angle_urad"), 0.0, 1e-4);
      EXPECT_NEAR(IsoValue(r, "size_BORE", "radius_error_um"), 0.0, 1e-6);
      EXPECT_NEAR(IsoValue(r, "position_BORE", "dy_um"), 0.0, 1e-6);
      EXPECT_NEAR(IsoValue(r, "flatness_FLOOR", "flatness_um"), 0.0, 1e-6);
    }
  }
}

TEST(IsoPieces, M1SquarenessOfXAndYShowsOnTheSquare) {
  // E_C(0X)Y = +e: a +Y move of y also moves the tool -e y in X, so the sides cut along Y lean
  // back: the angle between SQ_XP (+Y) and SQ_YN (+X) exceeds 90 deg by e; gdt's squareness is
  // asin(u . v) = -e (gdt/orientation.h).
  const auto m = Machine(kinematics::MachineType::kXyz);
  const TestPiece piece = MakeIsoPiece(ContourPieceParams::ForSize(320.0), m);
  kinematics::ErrorState e(m);
  ASSERT_TRUE(e.SetParameter(m, "E_C(0X)Y", 30e-6).ok());
  const auto r = EvaluateIso(piece, m, e, true);
  EXPECT_NEAR(IsoValue(r, "squareness_SQ_XP_SQ_YN", "angle_urad"), -30.0, 0.3);
  // The diamond's sides run at +-45 deg: a shear x' = x - e y turns both by e / 2, so their
  // angle is unchanged to first order (the diamond sees X/Y scale differences instead).
  EXPECT_NEAR(IsoValue(r, "squareness_DI_2_DI_1", "angle_urad"), 0.0, 0.05);
  // Straight sides stay straight; the circle's tool-centre path (radius 80 + 16 mm) becomes an
  // ellipse with axes at 45 deg: circularity = path radius x e = 96 mm x 30 urad = 2.88 um.
  EXPECT_NEAR(IsoValue(r, "straightness_SQ_XP", "straightness_um"), 0.0, 1e-4);
  EXPECT_NEAR(IsoValue(r, "circularity_CIRCLE", "circularity_um"), 96.0 * 30e-3, 0.01 * 2.88);
}

TEST(IsoPieces, M2FlatnessFollowsTheStraightnessOfX) {
  const auto m = Machine(kinematics::MachineType::kXyz);
  FaceMillingPieceParams params;
  const TestPiece piece = MakeIsoPiece(params, m);
  ASSERT_EQ(piece.features.size(), 2u);
  const auto zero = EvaluateIso(piece, m, kinematics::ErrorState(m), false);
  EXPECT_NEAR(IsoValue(zero, "flatness_FACE_P1", "flatness_um"), 0.0, 1e-6);
  // E_ZX(x) = c x^2 (um, x in mm): the face follows the tool, flatness = c (x_max^2 - x_min^2)
  // over the probed x range [-L/2 + margin, L/2 - margin] with x = 0 inside.
  auto e = kinematics::ParseErrorState(
      "effects:\n  - linear_error_motion: {symbol: E_ZX, coefficients_um_per_mm_pow: [0, 0, 2.0e-4]}\n", "<t>", m);
  ASSERT_TRUE(e.ok()) << e.status().ToString();
  const auto r = EvaluateIso(piece, m, *e, true);
  const double x_max = 0.5 * params.length_mm - ProbingOptions{}.edge_margin_mm;
  EXPECT_NEAR(IsoValue(r, "flatness_FACE_P1", "flatness_um"), 2.0e-4 * x_max * x_max, 1e-3);
  EXPECT_NEAR(IsoValue(r, "flatness_FACE_P2", "flatness_um"), 2.0e-4 * x_max * x_max, 1e-3);
  // The overlap strip belongs to the last pass: pass 2 regions start where pass 2 begins.
  auto c = CutPointAt(piece, "FACE_P2", Eigen::Vector3d(0, 0, params.height_mm));
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  EXPECT_NEAR(c->axes.y_mm, params.PassCenterY(1), 1e-9);
}

TEST(IsoPieces, ConeFrustumIsCutBySimultaneousFiveAxisMotion) {
  const auto m = Machine(kinematics::MachineType::kAcTable);
  const TestPiece piece = MakeIsoPiece(ConeFrustumParams{}, m);
  ASSERT_EQ(piece.features.size(), 3u);
  auto plan = MakeProbingPlan(piece);
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  double a_min = 1e9, a_max = -1e9;
  for (const auto& p : plan->points) {
    EXPECT_LT(kinematics::CutPointMismatch(m, p.cut), 1e-9) << p.feature;
    // The tool axis lies along the generatrix: tilted 15 deg from the cone axis.
    const Eigen::Vector3d tool_axis = kinematics::NominalToolAxisInPart(m, p.cut.axes);
    const NominalFeature* f = piece.Feature(p.feature);
    EXPECT_NEAR(std::acos(tool_axis.dot(f->axis)), DegToRad(15.0), 1e-9);
    EXPECT_NEAR(tool_axis.dot(p.normal_part), 0.0, 1e-9);
    a_min = std::min(a_min, RadToDeg(p.cut.axes.a_rad));
    a_max = std::max(a_max, RadToDeg(p.cut.axes.a_rad));
  }
  // A swings between -(15 - 10) and -(15 + 10) deg while C turns once.
  EXPECT_NEAR(a_min, -25.0, 0.2);
  EXPECT_NEAR(a_max, -5.0, 0.2);
  // The program interpolates A and C together.
  const auto& moves = piece.operations[0].passes[0].moves;
  int five_axis = 0;
  for (const auto& mv : moves) {
    if (mv.cutting && std::abs(mv.end.a_rad - mv.start.a_rad) > 0 && std::abs(mv.end.c_rad - mv.start.c_rad) > 0) {
      ++five_axis;
    }
  }
  EXPECT_EQ(five_axis, ConeFrustumParams{}.path_steps);
  const auto r = EvaluateIso(piece, m, kinematics::ErrorState(m), true);
  for (int k = 1; k <= 3; ++k) {
    EXPECT_NEAR(IsoValue(r, "circularity_CONE_" + std::to_string(k), "circularity_um"), 0.0, 1e-6);
    EXPECT_NEAR(IsoValue(r, "size_CONE_" + std::to_string(k), "radius_error_um"), 0.0, 1e-6);
  }
}

// The enriched cone piece: a second identical cone 130 mm along +X, cut by its own flank pass
// (a second operation), sections CONE2_1 .. CONE2_3; the machined piece is round again there, and
// the options that would overlap the cones or leave the tool off the plate are refused.
TEST(IsoPieces, SecondConeIsCutByItsOwnPass) {
  const auto m = Machine(kinematics::MachineType::kAcTable);
  ConeFrustumParams p;
  p.base_size_mm = 380;
  p.second_cone_offset_mm = 130;
  const TestPiece piece = MakeIsoPiece(p, m);
  ASSERT_EQ(piece.features.size(), 6u);
  ASSERT_EQ(piece.operations.size(), 2u);
  for (int k = 1; k <= 3; ++k) {
    const NominalFeature* a = piece.Feature("CONE_" + std::to_string(k));
    const NominalFeature* b = piece.Feature("CONE2_" + std::to_string(k));
    ASSERT_TRUE(a && b);
    EXPECT_EQ(b->origin_mm - a->origin_mm, Eigen::Vector3d(130, 0, 0));
    EXPECT_EQ(b->axis, a->axis);
  }
  auto plan = MakeProbingPlan(piece);
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  double x_min = 1e9, x_max = -1e9;
  for (const auto& pt : plan->points) {
    EXPECT_LT(kinematics::CutPointMismatch(m, pt.cut), 1e-9) << pt.feature;
    if (pt.feature.rfind("CONE2_", 0) == 0) {
      EXPECT_EQ(pt.cut.axes.op, 2);
      x_min = std::min(x_min, pt.cut.axes.x_mm);
      x_max = std::max(x_max, pt.cut.axes.x_mm);
    }
  }
  // The offset cone swings round the C axis: X spans about twice its offset.
  EXPECT_GT(x_max - x_min, 200.0);
  const auto r = EvaluateIso(piece, m, kinematics::ErrorState(m), true);
  for (int k = 1; k <= 3; ++k) EXPECT_NEAR(IsoValue(r, "circularity_CONE2_" + std::to_string(k), "circularity_um"), 0.0, 1e-6);
  ConeFrustumParams overlap = p;
  overlap.second_cone_offset_mm = 100;  // < 80 + 2 x 16
  EXPECT_FALSE(overlap.Validate().ok());
  ConeFrustumParams small_plate = p;
  small_plate.base_size_mm = 300;
  EXPECT_FALSE(small_plate.Validate().ok());
}

// The enriched cone piece's third cone, 130 mm along +Y, cut by a third operation (sections
// CONE3_1 .. CONE3_3), round when machined; it needs the second cone and room on the plate.
TEST(IsoPieces, ThirdConeIsCutByItsOwnPass) {
  const auto m = Machine(kinematics::MachineType::kAcTable);
  ConeFrustumParams p;
  p.base_size_mm = 380;
  p.second_cone_offset_mm = 130;
  p.third_cone_offset_mm = 130;
  const TestPiece piece = MakeIsoPiece(p, m);
  ASSERT_EQ(piece.features.size(), 9u);
  ASSERT_EQ(piece.operations.size(), 3u);
  for (int k = 1; k <= 3; ++k) {
    const NominalFeature* a = piece.Feature("CONE_" + std::to_string(k));
    const NominalFeature* c = piece.Feature("CONE3_" + std::to_string(k));
    ASSERT_TRUE(a && c);
    EXPECT_EQ(c->origin_mm - a->origin_mm, Eigen::Vector3d(0, 130, 0));
    EXPECT_EQ(c->axis, a->axis);
  }
  auto plan = MakeProbingPlan(piece);
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  double y_min = 1e9, y_max = -1e9;
  for (const auto& pt : plan->points) {
    EXPECT_LT(kinematics::CutPointMismatch(m, pt.cut), 1e-9) << pt.feature;
    if (pt.feature.rfind("CONE3_", 0) == 0) {
      EXPECT_EQ(pt.cut.axes.op, 3);
      y_min = std::min(y_min, pt.cut.axes.y_mm);
      y_max = std::max(y_max, pt.cut.axes.y_mm);
    }
  }
  EXPECT_GT(y_max - y_min, 200.0);  // it swings round the C axis too
  const auto r = EvaluateIso(piece, m, kinematics::ErrorState(m), true);
  for (int k = 1; k <= 3; ++k) EXPECT_NEAR(IsoValue(r, "circularity_CONE3_" + std::to_string(k), "circularity_um"), 0.0, 1e-6);
  ConeFrustumParams alone = p;
  alone.second_cone_offset_mm = 0;
  EXPECT_FALSE(alone.Validate().ok());
  ConeFrustumParams overlap = p;
  overlap.third_cone_offset_mm = 100;  // < 80 + 2 x 16
  EXPECT_FALSE(overlap.Validate().ok());
}

// The exact solve (kinematics::SimulateSurfacePoint on the cut point's sweep) and the first-order
// projection n0 . (S(0,0) - p0) agree to second order only if du, dv are tangent to the surface
// actually swept: this checks every cut model's sweep directions.
TEST(IsoPieces, SweepDirectionsAreTangentForEveryPiece) {
  struct P {
    PieceParams params;
    kinematics::MachineType type;
    double bound_mm = 2e-6;  // 2 um / 2 urad: the gap is curvature x slip^2 ~ 1e-6 mm at most
  };
  std::vector<P> pieces = {{TurningPieceParams{}, kinematics::MachineType::kAcTable},
                           {ContourPieceParams::ForSize(320), kinematics::MachineType::kAcTable},
                           {FaceMillingPieceParams{}, kinematics::MachineType::kAcTable},
                           {ConeFrustumParams{}, kinematics::MachineType::kAcTable}};
  ConeFrustumParams two_cones;
  two_cones.base_size_mm = 380;
  two_cones.second_cone_offset_mm = 130;
  // The offset cone sits up to 210 mm from the C axis: longer levers, larger slips.
  pieces.push_back({two_cones, kinematics::MachineType::kAcTable, 5e-6});
  ConeFrustumParams three_cones = two_cones;
  three_cones.third_cone_offset_mm = 130;
  pieces.push_back({three_cones, kinematics::MachineType::kAcTable, 5e-6});
  for (const P& pp : pieces) {
    const auto m = Machine(pp.type);
    const TestPiece piece = MakeIsoPiece(pp.params, m);
    SCOPED_TRACE(piece.name);
    auto plan = MakeProbingPlan(piece);
    ASSERT_TRUE(plan.ok());
    // The same error set at two scales: the exact - first-order gap must be second order (x100
    // for x10 errors). A sweep direction off the swept surface would make it first order.
    double worst[2] = {0, 0};
    for (int scale = 0; scale < 2; ++scale) {
      const double f = scale == 0 ? 1.0 : 10.0;
      kinematics::ErrorState e(m);
      for (const char* name : {"E_X0C", "E_Y0C", "E_A0C", "E_B0C", "E_Y0A", "E_Z0A", "E_B0A", "E_C(0X)Y", "E_B(0X)Z"}) {
        auto info = kinematics::LookupParameter(m, name);
        ASSERT_TRUE(info.ok()) << name;
        const bool angle = info->quantity == kinematics::Quantity::kAngle;
        ASSERT_TRUE(e.SetParameter(m, name, f * (angle ? 2e-6 : 0.002)).ok()) << name;
      }
      kinematics::Workspace ws;
      for (const auto& p : plan->points) {
        auto exact = kinematics::SimulateSurfacePoint(m, e, p.cut, &ws);
        ASSERT_TRUE(exact.ok()) << p.feature << ": " << exact.status().ToString();
        const auto first = kinematics::SimulateSurfacePointFirstOrder(m, e, p.cut, &ws);
        worst[scale] = std::max(worst[scale], std::abs(exact->deviation_mm - first.deviation_mm));
      }
    }
    EXPECT_LT(worst[0], pp.bound_mm);
    EXPECT_GT(worst[1], 50.0 * worst[0]) << worst[0] << " " << worst[1];
  }
}

}  // namespace
}  // namespace tpcal::testpieces
