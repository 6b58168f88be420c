// The surface-point simulation: exact solve of S(u, v) = p0 + s n0, zero errors give zero
// deviation, agreement with the first-order path to second order, a physical turning case, the
// deviation Jacobian, and clear failures.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/units.h"
#include "kinematics/error_state.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/inverse_kinematics.h"
#include "kinematics/simulate.h"

namespace tpcal::kinematics {
namespace {

MachineModel Machine(MachineType t) {
  Result<MachineModel> m = MakeMachine(t);
  EXPECT_TRUE(m.ok());
  return *m;
}

// A random, consistent cut point: random state and contact; p0 = nominal S(0, 0); random unit
// normal and random sweeps (one axis-space, one possibly in the tool frame).
CutPoint RandomCut(const MachineModel& m, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> lin(-300.0, 300.0), rot(-3.0, 3.0), u(-1.0, 1.0);
  CutPoint c;
  c.axes.x_mm = lin(rng); c.axes.y_mm = lin(rng); c.axes.z_mm = lin(rng);
  c.axes.a_rad = m.type == MachineType::kAcTable ? rot(rng) : 0.0;
  c.axes.b_rad = m.type == MachineType::kAcTable ? 0.0 : rot(rng);
  c.axes.c_rad = rot(rng);
  c.axes.t_s = 500.0 * (1.0 + u(rng));
  c.contact_in_tool_mm = Eigen::Vector3d(4 * u(rng), 4 * u(rng), 4 * u(rng));
  c.nominal_point_mm = NominalToolPointInPart(m, c.axes, c.contact_in_tool_mm);
  c.du.axes = AxisDelta{u(rng), u(rng), u(rng), 0, 0, 0};
  c.dv.axes = AxisDelta{0, 0, 0, 0.002 * u(rng), 0.002 * u(rng), 0.004 * u(rng)};
  c.dv.contact_in_tool_mm = Eigen::Vector3d(0, 0, 0.5 * u(rng));
  // The nominal surface normal: perpendicular to both nominal sweep tangents (central
  // differences), with a random orientation sign.
  auto S = [&](double a, double b) {
    return NominalToolPointInPart(m, Advance(Advance(c.axes, c.du.axes, a), c.dv.axes, b),
                                  c.contact_in_tool_mm + a * c.du.contact_in_tool_mm + b * c.dv.contact_in_tool_mm);
  };
  const double h = 1e-4;
  const Eigen::Vector3d su = (S(h, 0) - S(-h, 0)) / (2 * h), sv = (S(0, h) - S(0, -h)) / (2 * h);
  // Real sweeps cross at a good angle (feed and spin, path and tool axis); redraw the others.
  if (std::abs(su.normalized().dot(sv.normalized())) > 0.8) return RandomCut(m, rng);
  c.nominal_normal = (u(rng) > 0 ? 1.0 : -1.0) * su.cross(sv).normalized();
  return c;
}

ErrorState SomeErrors(const MachineModel& m, double scale, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ErrorState e(m);
  for (const ParameterInfo& p : ParameterCatalog(m)) {
    EXPECT_TRUE(e.SetParameter(m, p.name, scale * u(rng) * (p.quantity == Quantity::kLength ? 20e-3 : 20e-6)).ok());
  }
  for (const AxisLink& l : m.links) {
    if (!IsRotary(l.axis)) continue;
    ErrorTerm f;
    f.kind = TermKind::kFourier;
    f.label = std::string("E_Y") + AxisLetter(l.axis);
    f.effects = {{l.axis, Component::kTy, 1.0}};
    f.argument = l.axis;
    f.orders = {2, 3};
    f.is_sine = {false, true};
    f.coefficients = {scale * 2e-3, scale * -1e-3};
    EXPECT_TRUE(e.AddTerm(m, f).ok());
  }
  ErrorTerm d;
  d.kind = TermKind::kExponentialDrift;
  d.label = "E_X0X";
  d.effects = {{Axis::kX, Component::kTx, 1.0}};
  d.tau_s = 600;
  d.coefficients = {scale * 8e-3};
  EXPECT_TRUE(e.AddTerm(m, d).ok());
  return e;
}

const MachineType kAll[] = {MachineType::kAcTable, MachineType::kBcTable, MachineType::kBheadCtable,
                            MachineType::kXyz};

TEST(Simulate, ZeroErrorsGiveZeroDeviation) {
  std::mt19937_64 rng(101);
  for (MachineType t : kAll) {
    const MachineModel m = Machine(t);
    const ErrorState none(m);
    Workspace ws;
    for (int i = 0; i < 200; ++i) {
      const CutPoint c = RandomCut(m, rng);
      EXPECT_LT(CutPointMismatch(m, c), 1e-9);
      Result<SurfacePoint> r = SimulateSurfacePoint(m, none, c, &ws);
      ASSERT_TRUE(r.ok()) << r.status().ToString();
      EXPECT_LT(std::abs(r->deviation_mm), 1e-9);  // brief: zero errors -> zero deviation to 1e-9 mm
      EXPECT_LT(std::abs(SimulateSurfacePointFirstOrder(m, none, c, &ws).deviation_mm), 1e-9);
    }
  }
}

TEST(Simulate, SolutionLiesOnTheActualSweptSurface) {
  std::mt19937_64 rng(102);
  for (MachineType t : kAll) {
    const MachineModel m = Machine(t);
    const ErrorState e = SomeErrors(m, 1.0, rng);
    Workspace ws;
    for (int i = 0; i < 100; ++i) {
      const CutPoint c = RandomCut(m, rng);
      Result<SurfacePoint> r = SimulateSurfacePoint(m, e, c, &ws);
      ASSERT_TRUE(r.ok()) << r.status().ToString();
      const AxisState s = Advance(Advance(c.axes, c.du.axes, r->u), c.dv.axes, r->v);
      const Eigen::Vector3d contact = c.contact_in_tool_mm + r->u * c.du.contact_in_tool_mm +
                                      r->v * c.dv.contact_in_tool_mm;
      const Eigen::Vector3d S = ToolPointInPart(m, e, s, contact, &ws);
      EXPECT_LT((S - r->point_mm).norm(), 1e-9) << MachineTypeName(t);
      EXPECT_LT((r->point_mm - c.nominal_point_mm - r->deviation_mm * c.nominal_normal).norm(), 1e-12);
      EXPECT_LE(r->iterations, 5);
    }
  }
}

TEST(Simulate, FirstOrderAgreesToSecondOrder) {
  // Truth: the exact solve. |s_exact - s_first| must shrink like lambda^2 when all errors are
  // scaled by lambda. At realistic size (lambda = 1: 20 um, 20 urad) the random sweeps, some of
  // them spins a few mm from the axis (curvature radius ~1 mm), keep it below 1e-3 mm.
  std::mt19937_64 rng(103);
  int checked = 0;
  for (MachineType t : kAll) {
    const MachineModel m = Machine(t);
    for (int i = 0; i < 40; ++i) {
      const uint64_t seed = rng();
      std::mt19937_64 r1(seed), r2(seed);
      const ErrorState e1 = SomeErrors(m, 1.0, r1);
      const ErrorState e2 = SomeErrors(m, 0.5, r2);
      const CutPoint c = RandomCut(m, rng);
      Workspace ws;
      Result<SurfacePoint> x1 = SimulateSurfacePoint(m, e1, c, &ws);
      Result<SurfacePoint> x2 = SimulateSurfacePoint(m, e2, c, &ws);
      ASSERT_TRUE(x1.ok() && x2.ok());
      const double d1 = std::abs(x1->deviation_mm - SimulateSurfacePointFirstOrder(m, e1, c, &ws).deviation_mm);
      const double d2 = std::abs(x2->deviation_mm - SimulateSurfacePointFirstOrder(m, e2, c, &ws).deviation_mm);
      EXPECT_LT(d1, 1e-3);
      if (d1 > 1e-10) {  // above rounding: the ratio shows the order
        EXPECT_NEAR(d1 / d2, 4.0, 0.6) << MachineTypeName(t) << " d1 " << d1 << " d2 " << d2;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(Simulate, TurnedRadiusFollowsRadialErrorMotion) {
  // ac_table, A = 0: S1 of seed 002 (r = 160 mm at z = 400.702) turned with the C table's radial
  // error motion E_XC(c) = e cos 2c. The table moves +X toward the tool, so the turned radius at
  // part azimuth theta = C is r - e cos 2 theta (conventions.h sign).
  const MachineModel m = Machine(MachineType::kAcTable);
  ErrorState e(m);
  ErrorTerm f;
  f.kind = TermKind::kFourier;
  f.label = "E_XC";
  f.effects = {{Axis::kC, Component::kTx, 1.0}};
  f.argument = Axis::kC;
  f.orders = {2};
  f.is_sine = {false};
  f.coefficients = {1.5e-3};
  ASSERT_TRUE(e.AddTerm(m, f).ok());
  Workspace ws;
  const double r = 160.0, z = 400.702;
  for (int k = 0; k < 16; ++k) {
    const double th = DegToRad(22.5 * k);
    CutPoint c;
    c.axes.x_mm = r;
    c.axes.z_mm = z;
    c.axes.c_rad = th;
    c.nominal_point_mm = Eigen::Vector3d(r * std::cos(th), r * std::sin(th), z);
    c.nominal_normal = Eigen::Vector3d(std::cos(th), std::sin(th), 0.0);
    c.du.axes.z_mm = 1.0;   // feed along Z
    c.dv.axes.c_rad = 1.0;  // spin
    ASSERT_LT(CutPointMismatch(m, c), 1e-9);
    Result<SurfacePoint> s = SimulateSurfacePoint(m, e, c, &ws);
    ASSERT_TRUE(s.ok());
    // The exact deviation also carries the slope of E_XC along the spin: second order, < 1e-8.
    EXPECT_NEAR(s->deviation_mm, -1.5e-3 * std::cos(2 * th), 1e-8) << k;
  }
}

TEST(Simulate, DeviationJacobianMatchesFiniteDifferences) {
  std::mt19937_64 rng(104);
  for (MachineType t : kAll) {
    const MachineModel m = Machine(t);
    ErrorState e = SomeErrors(m, 1.0, rng);
    const ActiveSet all = AllCoefficients(e);
    Workspace ws;
    for (int i = 0; i < 5; ++i) {
      const CutPoint c = RandomCut(m, rng);
      Result<SurfacePoint> s = SimulateSurfacePoint(m, e, c, &ws);
      ASSERT_TRUE(s.ok());
      Result<Eigen::RowVectorXd> J = SurfaceDeviationJacobian(m, e, all, c, *s);
      ASSERT_TRUE(J.ok());
      SimulateOptions tight;
      tight.tolerance_mm = 1e-12;
      for (int j = 0; j < all.size(); ++j) {
        const double x0 = e.coefficient(j);
        const double h = 1e-5 / std::max(1.0, std::abs((*J)(j)));
        e.set_coefficient(j, x0 + h);
        const double sp = SimulateSurfacePoint(m, e, c, &ws, tight)->deviation_mm;
        e.set_coefficient(j, x0 - h);
        const double sm = SimulateSurfacePoint(m, e, c, &ws, tight)->deviation_mm;
        e.set_coefficient(j, x0);
        EXPECT_NEAR((sp - sm) / (2 * h), (*J)(j), 1e-6 * (1 + std::abs((*J)(j))))
            << MachineTypeName(t) << " " << e.coefficient_info(j).name;
      }
    }
  }
}

TEST(Simulate, BadCutPointsFailClearly) {
  const MachineModel m = Machine(MachineType::kAcTable);
  const ErrorState none(m);
  Workspace ws;
  CutPoint c;
  c.axes.x_mm = 100;
  c.nominal_point_mm = Eigen::Vector3d(100, 0, 0);
  c.nominal_normal = Eigen::Vector3d(1, 0, 0);
  c.du.axes.z_mm = 1;
  c.dv.axes.x_mm = 1;  // sweeps along the normal: [S_u S_v n0] singular
  Result<SurfacePoint> r = SimulateSurfacePoint(m, none, c, &ws);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kDegenerate);
  c.dv.axes = AxisDelta{};
  c.dv.axes.c_rad = 1;
  c.nominal_normal = Eigen::Vector3d(2, 0, 0);
  r = SimulateSurfacePoint(m, none, c, &ws);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
  SimulateOptions bad;
  bad.max_iterations = 0;
  EXPECT_FALSE(bad.Validate().ok());
}

}  // namespace
}  // namespace tpcal::kinematics
