// The ball-bar measurement model (kinematics/ballbar.h). Truths are closed forms of the exact
// chain (kinematics/conventions.h), derived in each test; tolerances:
//   kBbNominalTol_um = 1e-9: zero errors, the only deviation is double rounding of ~300 mm
//     coordinates through a few transforms (eps * 300 mm = 7e-14 mm = 7e-11 um per operation);
//   kBbExactTol_um = 1e-6: an exact closed form against the exact chain (rounding, and the
//     nominal commands polished to rounding);
//   first-order forms (seed 003 eq. 9, ISO 230-4) within their second-order remainder, stated.
#include "kinematics/ballbar.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/units.h"
#include "kinematics/error_parameters.h"
#include "kinematics/machine_yaml.h"

namespace tpcal::kinematics {
namespace {

constexpr double kBbNominalTol_um = 1e-9;
constexpr double kBbExactTol_um = 1e-6;

MachineModel BbMachine(MachineType type) {
  auto m = MakeMachine(type);
  EXPECT_TRUE(m.ok()) << m.status().ToString();
  return *m;
}

BallbarInstallation BbInstall(BallbarKind kind, Axis axis, Eigen::Vector3d w, Eigen::Vector3d t, double length_mm,
                              int sense = +1) {
  BallbarInstallation i;
  i.name = "test";
  i.kind = kind;
  i.axis = axis;
  i.workpiece_ball_in_part_mm = w;
  i.tool_ball_in_tool_mm = t;
  i.nominal_length_mm = length_mm;
  i.sense = sense;
  return i;
}

BallbarInstallation BbCircle(BallbarPlane plane, double radius_mm) {
  BallbarInstallation i = BbInstall(BallbarKind::kCircle, Axis::kC, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                    radius_mm);
  i.plane = plane;
  return i;
}

double BbDl(const MachineModel& m, const ErrorState& e, const BallbarInstallation& inst, double angle_deg) {
  auto g = MakeBallbarGeometry(m, inst);
  EXPECT_TRUE(g.ok()) << g.status().ToString();
  Workspace ws;
  auto dl = SimulateBallbarDlUm(m, e, *g, angle_deg, 0.0, &ws);
  EXPECT_TRUE(dl.ok()) << dl.status().ToString();
  return dl.ok() ? *dl : std::nan("");
}

// Seed 003's installations (C table: radial / tangential / axial with the ball 150 mm from the
// C axis, 50 mm above the table; B head: tool ball 150 mm below the B axis, which MakeMachine puts
// 300 mm above the tool reference point) and the three circle planes.
std::vector<BallbarInstallation> BbAllKinds() {
  const Eigen::Vector3d w_c(150.0, 0.0, 50.0), t_b(0.0, 0.0, 150.0), w_b(0.0, 0.0, 0.0);
  std::vector<BallbarInstallation> out;
  for (BallbarKind k : {BallbarKind::kRadial, BallbarKind::kTangential, BallbarKind::kAxial})
    for (int sense : {+1, -1}) {
      out.push_back(BbInstall(k, Axis::kC, w_c, Eigen::Vector3d::Zero(), 100.0, sense));
      out.push_back(BbInstall(k, Axis::kB, w_b, t_b, 150.0, sense));
    }
  for (BallbarPlane p : {BallbarPlane::kXY, BallbarPlane::kYZ, BallbarPlane::kZX}) out.push_back(BbCircle(p, 150.0));
  return out;
}

TEST(Ballbar, ZeroErrorsGiveZeroDeviationForEveryKind) {
  const MachineModel m = BbMachine(MachineType::kBheadCtable);
  const ErrorState zero(m);
  for (const BallbarInstallation& inst : BbAllKinds())
    for (double a = -100.0; a <= 360.0; a += 20.0)
      EXPECT_NEAR(BbDl(m, zero, inst, a), 0.0, kBbNominalTol_um)
          << BallbarKindName(inst.kind) << " axis " << AxisLetter(inst.axis) << " sense " << inst.sense << " at " << a;
}

TEST(Ballbar, TheBarKeepsItsDirectionOnTheTurnedElement) {
  // C table, radial, sense +1: the nominal tool ball stays at part (250, 0, 50) at every C.
  const MachineModel m = BbMachine(MachineType::kBheadCtable);
  auto g = MakeBallbarGeometry(m, BbInstall(BallbarKind::kRadial, Axis::kC, {150, 0, 50}, {0, 0, 0}, 100.0));
  ASSERT_TRUE(g.ok());
  for (double c : {0.0, 40.0, 200.0})
    EXPECT_LT((BallbarTargetInPart(m, *g, c) - Eigen::Vector3d(250, 0, 50)).norm(), 1e-12) << c;
  // B head, radial: at B = 0 the bar hangs along -Z from the tool ball's side (d = -Z in the tool
  // frame); sense -1 puts the tool ball 150 mm above the workpiece ball.
  auto gb = MakeBallbarGeometry(m, BbInstall(BallbarKind::kRadial, Axis::kB, {0, 0, 0}, {0, 0, 150}, 150.0, -1));
  ASSERT_TRUE(gb.ok());
  EXPECT_LT((gb->bar_direction - Eigen::Vector3d(0, 0, -1)).norm(), 1e-12);
  EXPECT_LT((gb->axis_direction - Eigen::Vector3d(0, 1, 0)).norm(), 1e-12);
  EXPECT_LT((BallbarTargetInPart(m, *gb, 0.0) - Eigen::Vector3d(0, 0, 150)).norm(), 1e-12);
}

// E_X0C = +e (conventions.h): the C line AND the table move +e in machine X, so the workpiece
// ball is at R w + e X (R the table turn; the tool branch is untouched) while the tool ball stays
// on its nominal R (w + s L0 d). With the ball on part +X, d = +X (radial) and R d . X = cos(C)
// (the table turns by -C, cos is even):
//   bar = s L0 R d - e X,  length = sqrt(L0^2 - 2 s L0 e cos C + e^2).
// Sense -1 (tool ball between the C axis and the workpiece ball): dl = +e cos C to first order,
// the remainder e^2 sin^2 C / (2 L0) <= (10 um)^2 / (2 * 100 mm) = 5e-4 um.
TEST(Ballbar, CTableLocationErrorGivesOneLobeOnARadialBar) {
  constexpr double e_um = 10.0, L0 = 100.0;
  constexpr double kSecondOrder_um = e_um * e_um / (2.0 * MmToUm(L0));
  for (MachineType type : {MachineType::kBheadCtable, MachineType::kAcTable}) {
    const MachineModel m = BbMachine(type);
    ErrorState e(m);
    ASSERT_TRUE(e.SetParameter(m, "E_X0C", UmToMm(e_um)).ok());
    const auto inst = BbInstall(BallbarKind::kRadial, Axis::kC, {150, 0, 50}, {0, 0, 0}, L0, -1);
    for (double c = 0.0; c <= 360.0; c += 20.0) {
      const double cos_c = std::cos(DegToRad(c)), ee = UmToMm(e_um);
      const double exact_um = MmToUm(std::sqrt(L0 * L0 + 2.0 * L0 * ee * cos_c + ee * ee) - L0);
      const double dl = BbDl(m, e, inst, c);
      EXPECT_NEAR(dl, exact_um, kBbExactTol_um) << MachineTypeName(type) << " C " << c;
      EXPECT_NEAR(dl, e_um * cos_c, kSecondOrder_um + kBbExactTol_um) << MachineTypeName(type) << " C " << c;
    }
  }
}

// The other C-table kinds pin their directions. E_Y0C = +e moves the table ball +e in machine Y;
// tangential (d = Z x X = +Y on the part), sense +1: bar = L0 RotZ(-C) Y - e Y with
// RotZ(-C) Y = (sin C, cos C, 0), length = sqrt(L0^2 - 2 L0 e cos C + e^2). E_Z0C = +e lifts
// the table ball; axial (d = +Z), sense +1: bar = (L0 - e) Z, dl = -e at every C.
TEST(Ballbar, CTableTangentialAndAxialDirections) {
  constexpr double e_um = 10.0, L0 = 150.0;
  const double ee = UmToMm(e_um);
  const MachineModel m = BbMachine(MachineType::kBheadCtable);
  ErrorState ey(m), ez(m);
  ASSERT_TRUE(ey.SetParameter(m, "E_Y0C", ee).ok());
  ASSERT_TRUE(ez.SetParameter(m, "E_Z0C", ee).ok());
  const auto tangential = BbInstall(BallbarKind::kTangential, Axis::kC, {100, 0, 50}, {0, 0, 0}, L0);
  const auto axial = BbInstall(BallbarKind::kAxial, Axis::kC, {0, 0, 50}, {0, 0, 0}, L0);
  for (double c = 0.0; c <= 360.0; c += 20.0) {
    const double cos_c = std::cos(DegToRad(c));
    EXPECT_NEAR(BbDl(m, ey, tangential, c), MmToUm(std::sqrt(L0 * L0 - 2.0 * L0 * ee * cos_c + ee * ee) - L0),
                kBbExactTol_um) << "C " << c;
    EXPECT_NEAR(BbDl(m, ez, axial, c), -e_um, kBbExactTol_um) << "C " << c;
  }
}

// E_X0B = +e on the B head: the head (and the tool ball with it) moves +e in machine X. Radial,
// sense -1: bar = L0 RotY(B) Z + e X = L0 (sin B, 0, cos B) + e X, so
// length = sqrt(L0^2 + 2 L0 e sin B + e^2): dl = e sin B to first order (seed 003 eq. 28: the
// radial bar at B reads delta_Bx sin B).
TEST(Ballbar, BHeadLocationErrorTurnsWithTheHead) {
  constexpr double e_um = 10.0, L0 = 150.0;
  const MachineModel m = BbMachine(MachineType::kBheadCtable);
  ErrorState e(m);
  ASSERT_TRUE(e.SetParameter(m, "E_X0B", UmToMm(e_um)).ok());
  const auto inst = BbInstall(BallbarKind::kRadial, Axis::kB, {0, 0, 0}, {0, 0, 150}, L0, -1);
  for (double b = -100.0; b <= 0.0; b += 10.0) {
    const double sin_b = std::sin(DegToRad(b)), ee = UmToMm(e_um);
    EXPECT_NEAR(BbDl(m, e, inst, b), MmToUm(std::sqrt(L0 * L0 + 2.0 * L0 * ee * sin_b + ee * ee) - L0), kBbExactTol_um)
        << "B " << b;
  }
}

// ISO 230-4 circle in XY about the workpiece ball at the origin (centre commands X = Y = 0, so the
// squareness adds no offset). E_C(0X)Y = +S (conventions.h): a +Y move of y moves the tool
// -S y in X; exactly, Y travels along (-sin S, cos S). Tool ball - centre =
// R (cos phi - sin S sin phi, cos S sin phi), length = R sqrt(1 - sin S sin 2 phi):
// dl = -(S R / 2) sin 2 phi, the classic 2-lobe ellipse (long axis along phi = -45 deg), with a
// remainder R S^2 / 8 = 150 mm * (20e-6)^2 / 8 = 7.5e-6 um.
TEST(Ballbar, SquarenessGivesTheTwoLobeEllipse) {
  constexpr double S = 20e-6, R = 150.0, kEllipseTol_um = 1e-3;
  for (MachineType type : {MachineType::kXyz, MachineType::kBheadCtable}) {
    const MachineModel m = BbMachine(type);
    ErrorState e(m);
    ASSERT_TRUE(e.SetParameter(m, "E_C(0X)Y", S).ok());
    const auto inst = BbCircle(BallbarPlane::kXY, R);
    for (double phi = 0.0; phi < 360.0; phi += 15.0) {
      const double p = DegToRad(phi);
      const double dl = BbDl(m, e, inst, phi);
      EXPECT_NEAR(dl, -MmToUm(S * R / 2.0) * std::sin(2.0 * p), kEllipseTol_um) << MachineTypeName(type) << " " << phi;
      EXPECT_NEAR(dl, MmToUm(R * std::sqrt(1.0 - std::sin(S) * std::sin(2.0 * p)) - R), kBbExactTol_um) << phi;
    }
  }
}

// E_XX = c1 x (linear_error_motion polynomial, tool-side X: the tool reaches x (1 + c1)). Circle
// about the origin: length = R sqrt((1 + c1)^2 cos^2 phi + sin^2 phi), dl = c1 R cos^2 phi to
// first order, remainder <= c1^2 R / 8 = (1e-5)^2 * 150 mm / 8 = 1.9e-6 um.
TEST(Ballbar, ScaleErrorGivesCosSquared) {
  constexpr double c1 = 1e-5, R = 150.0, kScaleTol_um = 1e-5;
  const MachineModel m = BbMachine(MachineType::kXyz);
  ErrorState e(m);
  auto active = ActivateParameters(m, &e, {"E_XX.c1"});
  ASSERT_TRUE(active.ok()) << active.status().ToString();
  e.set_coefficient(active->coefficients[0], c1);
  const auto inst = BbCircle(BallbarPlane::kXY, R);
  for (double phi = 0.0; phi < 360.0; phi += 15.0) {
    const double cp = std::cos(DegToRad(phi)), sp = std::sin(DegToRad(phi));
    const double dl = BbDl(m, e, inst, phi);
    EXPECT_NEAR(dl, MmToUm(c1 * R) * cp * cp, kScaleTol_um) << phi;
    EXPECT_NEAR(dl, MmToUm(R * std::sqrt((1 + c1) * (1 + c1) * cp * cp + sp * sp) - R), kBbExactTol_um) << phi;
  }
}

TEST(Ballbar, InstallationsTheMachineCannotRunAreRefused) {
  const MachineModel m = BbMachine(MachineType::kBheadCtable);
  // Radial with the workpiece ball on the C axis: no radial direction.
  auto on_axis = MakeBallbarGeometry(m, BbInstall(BallbarKind::kRadial, Axis::kC, {0, 0, 50}, {0, 0, 0}, 100.0));
  ASSERT_FALSE(on_axis.ok());
  EXPECT_EQ(on_axis.status().code(), StatusCode::kInvalidArgument);
  // Axial on the C axis is the paper's L = 0 installation: fine.
  EXPECT_TRUE(MakeBallbarGeometry(m, BbInstall(BallbarKind::kAxial, Axis::kC, {0, 0, 50}, {0, 0, 0}, 100.0)).ok());
  // An A axis the machine lacks, turned or held.
  auto no_a = MakeBallbarGeometry(m, BbInstall(BallbarKind::kAxial, Axis::kA, {0, 0, 50}, {0, 0, 0}, 100.0));
  EXPECT_EQ(no_a.status().code(), StatusCode::kInvalidArgument);
  auto held = BbInstall(BallbarKind::kAxial, Axis::kC, {0, 0, 50}, {0, 0, 0}, 100.0);
  held.hold_deg[Axis::kA] = 10.0;
  EXPECT_EQ(MakeBallbarGeometry(m, held).status().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace tpcal::kinematics

namespace tpcal::kinematics {
namespace {

// Every installation of the seed 003 sample runs on the sample machine and reads dl = 0 on it
// when nominal, over the paper's angles (C 0..360 by 20, B -100..0 by 5).
TEST(Ballbar, TheSeed003SampleRunsOnItsMachine) {
  auto m = LoadMachineModel(std::string(TPCAL_SOURCE_DIR) + "/samples/machines/bhead_ctable.yaml");
  ASSERT_TRUE(m.ok()) << m.status().ToString();
  auto setup = LoadBallbarSetup(std::string(TPCAL_SOURCE_DIR) + "/samples/ballbar/seed003_setups.yaml");
  ASSERT_TRUE(setup.ok()) << setup.status().ToString();
  const ErrorState zero(*m);
  for (const BallbarInstallation& inst : setup->installations) {
    const bool b = inst.axis == Axis::kB;
    for (double a = b ? -100.0 : 0.0; a <= (b ? 0.0 : 360.0); a += b ? 5.0 : 20.0)
      EXPECT_NEAR(BbDl(*m, zero, inst, a), 0.0, kBbNominalTol_um) << inst.name << " at " << a;
  }
}

}  // namespace
}  // namespace tpcal::kinematics
