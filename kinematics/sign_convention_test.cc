// One-parameter simulations: the direction of each effect matches the sign documented in
// kinematics/conventions.h and the catalog descriptions (ISO 230-1 and ISO 841).
#include <gtest/gtest.h>

#include <cmath>

#include "core/units.h"
#include "kinematics/error_state.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/machine_model.h"

namespace tpcal::kinematics {
namespace {

// Second-order terms of 1e-5 rad errors on 500 mm lever arms: 1e-10 * 500 = 5e-8 mm; exact
// expectations below are first order, so compare to 1e-7 mm.
constexpr double kTol_mm = 1e-7;

MachineModel Machine(MachineType t, const MachineLayout& layout = {}) {
  Result<MachineModel> m = MakeMachine(t, layout);
  EXPECT_TRUE(m.ok());
  return *m;
}

Eigen::Vector3d PointWith(const MachineModel& m, const char* name, double value, const AxisState& s,
                          const Eigen::Vector3d& contact = Eigen::Vector3d::Zero()) {
  ErrorState e(m);
  EXPECT_TRUE(e.SetParameter(m, name, value).ok()) << name;
  Workspace ws;
  return ToolPointInPart(m, e, s, contact, &ws);
}

AxisState At(double x, double y, double z, double a_deg = 0, double b_deg = 0, double c_deg = 0) {
  AxisState s;
  s.x_mm = x; s.y_mm = y; s.z_mm = z;
  s.a_rad = DegToRad(a_deg); s.b_rad = DegToRad(b_deg); s.c_rad = DegToRad(c_deg);
  return s;
}

TEST(SignConvention, Iso841NominalRotaryDirections) {
  const MachineModel ac = Machine(MachineType::kAcTable);
  // A positive C command: the tool at machine (140, 0, z) cuts part azimuth +C.
  const Eigen::Vector3d p = NominalToolPointInPart(ac, At(140, 0, 10, 0, 0, 30), Eigen::Vector3d::Zero());
  EXPECT_NEAR(std::atan2(p.y(), p.x()), DegToRad(30), 1e-12);
  // At A = -90 deg part +Z points along machine -Y.
  ErrorState none(ac);
  Workspace ws;
  const Rigid3 mp = MachineFromPart(ac, none, At(0, 0, 0, -90), &ws);
  EXPECT_LT((mp.linear() * Eigen::Vector3d::UnitZ() - Eigen::Vector3d(0, -1, 0)).norm(), 1e-12);
  // A positive B on a B/C table or a B head turns the tool axis (in the part) from +Z to +X.
  for (MachineType t : {MachineType::kBcTable, MachineType::kBheadCtable}) {
    const MachineModel m = Machine(t);
    const Eigen::Vector3d axis = NominalToolAxisInPart(m, At(0, 0, 0, 0, 90, 0));
    EXPECT_LT((axis - Eigen::Vector3d::UnitX()).norm(), 1e-12) << MachineTypeName(t);
  }
  // A positive linear command moves the tool positively relative to the part, also when the
  // table carries the axis (X' = -X, ISO 841).
  const MachineModel vmc = Machine(MachineType::kXyz, {{Axis::kY, Axis::kX}, {Axis::kZ}});
  const Eigen::Vector3d q = NominalToolPointInPart(vmc, At(10, 20, 30), Eigen::Vector3d::Zero());
  EXPECT_LT((q - Eigen::Vector3d(10, 20, 30)).norm(), 1e-12);
}

TEST(SignConvention, RotaryLocationErrors) {
  const MachineModel ac = Machine(MachineType::kAcTable);
  const double d = 0.010, e = 20e-6;
  // E_X0C = +10 um moves the C line and the table +X: the tool at machine (x, y, z) lands at
  // part (x - d, y, z) at A = C = 0; at C = 90 deg the table's -X is the part's -Y.
  EXPECT_LT((PointWith(ac, "E_X0C", d, At(140, 5, 30)) - Eigen::Vector3d(140 - d, 5, 30)).norm(), kTol_mm);
  EXPECT_LT((PointWith(ac, "E_X0C", d, At(140, 0, 30, 0, 0, 90)) -
             Eigen::Vector3d(0, 140 - d, 30)).norm(), kTol_mm);
  // E_B0C = +20 urad tilts the C axis from +Z toward +X: the part point under the tool at
  // height z is at part x = -e z.
  EXPECT_LT((PointWith(ac, "E_B0C", e, At(0, 0, 400)) - Eigen::Vector3d(-e * 400, 0, 400)).norm(), kTol_mm);
  {
    ErrorState s(ac);
    ASSERT_TRUE(s.SetParameter(ac, "E_B0C", e).ok());
    Workspace ws;
    const Eigen::Vector3d c_axis = MachineFromPart(ac, s, At(0, 0, 0), &ws).linear().col(2);
    EXPECT_NEAR(c_axis.x(), e, 1e-12);
  }
  // E_A0C = +e tilts C from +Z toward -Y.
  EXPECT_LT((PointWith(ac, "E_A0C", e, At(0, 0, 400)) - Eigen::Vector3d(0, e * 400, 400)).norm(), kTol_mm);
  // E_C0C = +e turns the table +e about +Z: the tool at machine azimuth 0 cuts part azimuth C - e.
  const Eigen::Vector3d c = PointWith(ac, "E_C0C", e, At(140, 0, 0, 0, 0, 30));
  EXPECT_NEAR(std::atan2(c.y(), c.x()), DegToRad(30) - e, 1e-12);
  // E_Y0A = +d moves the A line and the cradle +Y: at A = 0 the tool lands at part y - d, and the
  // C line (carried by A) moves with it (ISO 230-1: C errors are relative to A).
  EXPECT_LT((PointWith(ac, "E_Y0A", d, At(140, 0, 30)) - Eigen::Vector3d(140, -d, 30)).norm(), kTol_mm);
  // E_Y(0A)C is an alias of E_Y0C.
  EXPECT_LT((PointWith(ac, "E_Y(0A)C", d, At(140, 0, 30)) - PointWith(ac, "E_Y0C", d, At(140, 0, 30))).norm(), 1e-15);
  // E_Z0A = +d at A = -90: the cradle moves +Z in the machine, i.e. the tool at machine
  // (0, -z, r) is at part (0, r - d, z): at A = -90, C = 0 the part's +Y is machine +Z.
  const Eigen::Vector3d z = PointWith(ac, "E_Z0A", d, At(0, -300, 170, -90));
  EXPECT_LT((z - Eigen::Vector3d(0, 170 - d, 300)).norm(), kTol_mm);
}

TEST(SignConvention, LinearSquareness) {
  const MachineModel ac = Machine(MachineType::kAcTable);
  const double e = 20e-6;
  // E_C(0X)Y = +e: a +Y move of y also moves the tool -e y in X.
  EXPECT_LT((PointWith(ac, "E_C(0X)Y", e, At(0, 100, 0)) - Eigen::Vector3d(-e * 100, 100, 0)).norm(), kTol_mm);
  // E_B(0X)Z = +e: a +Z move of z also moves the tool +e z in X.
  EXPECT_LT((PointWith(ac, "E_B(0X)Z", e, At(0, 0, 100)) - Eigen::Vector3d(e * 100, 0, 100)).norm(), kTol_mm);
  // E_A(0Y)Z = +e: a +Z move of z also moves the tool -e z in Y.
  EXPECT_LT((PointWith(ac, "E_A(0Y)Z", e, At(0, 0, 100)) - Eigen::Vector3d(0, -e * 100, 100)).norm(), kTol_mm);
  // Same relative effect when the table carries X and Y (the direction of travel is geometry).
  const MachineModel vmc = Machine(MachineType::kXyz, {{Axis::kY, Axis::kX}, {Axis::kZ}});
  EXPECT_LT((PointWith(vmc, "E_C(0X)Y", e, At(0, 100, 0)) - Eigen::Vector3d(-e * 100, 100, 0)).norm(), kTol_mm);
}

TEST(SignConvention, ErrorMotions) {
  const MachineModel ac = Machine(MachineType::kAcTable);
  Workspace ws;
  // E_XX(x) = +e (tool-side X): the tool reaches x + e.
  {
    ErrorState s(ac);
    ErrorTerm t;
    t.kind = TermKind::kPolynomial;
    t.label = "E_XX";
    t.effects = {{Axis::kX, Component::kTx, 1.0}};
    t.argument = Axis::kX;
    t.powers = {1};
    t.coefficients = {5e-6};  // 5 um per m: scale error
    ASSERT_TRUE(s.AddTerm(ac, t).ok());
    EXPECT_NEAR(ToolPointInPart(ac, s, At(200, 0, 0), Eigen::Vector3d::Zero(), &ws).x(), 200 + 1e-3, 1e-12);
  }
  // E_XC(c) radial error motion of the C table = +e cos 2c: the table moves +X, so the tool at
  // machine (r, 0, z) lands at part radius r - e cos 2c (the turned radius shrinks).
  {
    ErrorState s(ac);
    ErrorTerm t;
    t.kind = TermKind::kFourier;
    t.label = "E_XC";
    t.effects = {{Axis::kC, Component::kTx, 1.0}};
    t.argument = Axis::kC;
    t.orders = {2};
    t.is_sine = {false};
    t.coefficients = {2e-3};
    ASSERT_TRUE(s.AddTerm(ac, t).ok());
    for (double c_deg : {0.0, 30.0, 45.0, 200.0}) {
      const Eigen::Vector3d p = ToolPointInPart(ac, s, At(160, 0, 400, 0, 0, c_deg), Eigen::Vector3d::Zero(), &ws);
      EXPECT_NEAR(p.head<2>().norm(), 160 - 2e-3 * std::cos(2 * DegToRad(c_deg)), 1e-9) << c_deg;
    }
  }
  // E_BC tilt error motion = +e: the table tilts about +Y through the pivot (the MCS origin):
  // at height z the part point under the tool is at part x = -e z.
  {
    ErrorState s(ac);
    ErrorTerm t;
    t.kind = TermKind::kConstant;
    t.label = "E_BC";
    t.quantity = Quantity::kAngle;
    t.effects = {{Axis::kC, Component::kRy, 1.0}};
    t.condition.axis = Axis::kA;  // only with the table horizontal
    t.coefficients = {10e-6};
    ASSERT_TRUE(s.AddTerm(ac, t).ok());
    EXPECT_NEAR(ToolPointInPart(ac, s, At(0, 0, 400), Eigen::Vector3d::Zero(), &ws).x(), -4e-3, 1e-9);
    EXPECT_NEAR(ToolPointInPart(ac, s, At(0, 0, 400, -90), Eigen::Vector3d::Zero(), &ws).x(), 0.0, 1e-12);
  }
}

TEST(SignConvention, ThermalDriftFollowsTime) {
  const MachineModel ac = Machine(MachineType::kAcTable);
  ErrorState s(ac);
  ErrorTerm t;
  t.kind = TermKind::kExponentialDrift;
  t.label = "E_X0C";
  t.effects = {{Axis::kC, Component::kTx, 1.0}};
  t.tau_s = 1200;
  t.coefficients = {8e-3};
  ASSERT_TRUE(s.AddTerm(ac, t).ok());
  Workspace ws;
  AxisState a = At(140, 0, 0);
  a.t_s = 0;
  EXPECT_NEAR(ToolPointInPart(ac, s, a, Eigen::Vector3d::Zero(), &ws).x(), 140, 1e-12);
  a.t_s = 1200;
  EXPECT_NEAR(ToolPointInPart(ac, s, a, Eigen::Vector3d::Zero(), &ws).x(), 140 - 8e-3 * (1 - std::exp(-1.0)), 1e-12);
}

TEST(SignConvention, HeadLocationErrors) {
  // bhead_ctable: E_B0B = +e turns the head +e about +Y: the tool axis tips toward +X and the
  // tool tip, 300 mm below the pivot, swings to R_y(e) (0, 0, -300) = (-300 e, 0, -300): -X.
  const MachineModel bh = Machine(MachineType::kBheadCtable);
  ErrorState s(bh);
  ASSERT_TRUE(s.SetParameter(bh, "E_B0B", 10e-6).ok());
  Workspace ws;
  const Rigid3 pt = PartFromTool(bh, s, At(0, 0, 0), &ws);
  EXPECT_NEAR(pt.linear().col(2).x(), 10e-6, 1e-12);
  EXPECT_NEAR(pt.translation().x(), -300 * 10e-6, 1e-9);
}

TEST(SignConvention, Seed002LineParametersAtToolPointLevel) {
  // Kinematics of the seed 002 "line" parameters (SEED002_SIGNS.md): dx_CR(0) = d moves the C
  // line +X (at every A) without moving the table at C = 0, so the tool point in the part shifts by
  // (I - RotZ(C)) (d, 0, 0): nothing at C = 0, (2d, 0, 0) at C = 180 deg.
  const MachineModel ac = Machine(MachineType::kAcTable);
  const double d = 0.010;
  const Eigen::Vector3d nominal = NominalToolPointInPart(ac, At(140, 0, 30, 0, 0, 180), Eigen::Vector3d::Zero());
  EXPECT_LT((PointWith(ac, "dx_CR(0)", d, At(140, 0, 30, 0, 0, 0)) - Eigen::Vector3d(140, 0, 30)).norm(), 1e-12);
  EXPECT_LT((PointWith(ac, "dx_CR(0)", d, At(140, 0, 30, 0, 0, 180)) - nominal - Eigen::Vector3d(2 * d, 0, 0)).norm(), kTol_mm);
  // The same at A = -90: A turns about X, so the X position of the C line does not depend on A.
  EXPECT_LT((PointWith(ac, "dx_CR(0)", d, At(140, 0, 30, -90, 0, 180)) -
             NominalToolPointInPart(ac, At(140, 0, 30, -90, 0, 180), Eigen::Vector3d::Zero()) -
             Eigen::Vector3d(2 * d, 0, 0)).norm(), kTol_mm);
  EXPECT_LT((PointWith(ac, "dx_CR(0)", d, At(140, 0, 30, -90, 0, 0)) -
             NominalToolPointInPart(ac, At(140, 0, 30, -90, 0, 0), Eigen::Vector3d::Zero())).norm(), 1e-12);
  // dz_AR(-90) = d: the A line at Z = d; turning from A = 0 to -90 about it shifts the part by
  // (I - RotX(90)) (0, 0, d) = (0, d, d) in the machine: the tool at machine (0, y, r) is at
  // part (0, r - d, -(y - d)) at C = 0.
  EXPECT_LT((PointWith(ac, "dz_AR(-90)", d, At(0, -300, 170, -90)) - Eigen::Vector3d(0, 170 - d, 300 + d)).norm(), kTol_mm);
  // dy_AR(-90) = d: A line at Y = d, part shift (0, d, -d) in the machine, i.e. the tool at
  // machine (0, y, r) is at part (0, r + d, -(y - d)); the C line keeps its offset to A (it is at
  // part (0, d)), so the turned radius is unchanged and the axial position moves +d in part z.
  const Eigen::Vector3d y = PointWith(ac, "dy_AR(-90)", d, At(0, -300, 170, -90));
  EXPECT_LT((y - Eigen::Vector3d(0, 170 + d, 300 + d)).norm(), kTol_mm);
  EXPECT_NEAR((y.head<2>() - Eigen::Vector2d(0, d)).norm(), 170, kTol_mm);
  // dy_CA(-90) = d: the C line d off the A line along the table's Y (machine +Z): at C = 0 the
  // table does not move; the spin axis is at part y = d, so the turned radius is r - d.
  const Eigen::Vector3d ca = PointWith(ac, "dy_CA(-90)", d, At(0, -300, 170, -90, 0, 0));
  EXPECT_LT((ca - Eigen::Vector3d(0, 170, 300)).norm(), kTol_mm);
  const Eigen::Vector3d ca180 = PointWith(ac, "dy_CA(-90)", d, At(0, -300, 170, -90, 0, 180));
  EXPECT_NEAR((ca180.head<2>() - Eigen::Vector2d(0, d)).norm(), 170 - d, kTol_mm);
}

}  // namespace
}  // namespace tpcal::kinematics
