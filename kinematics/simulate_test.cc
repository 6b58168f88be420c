// The surface-point simulation: exact solve of S(u, v) = p0 + s n0, zero errors give zero
// deviation, agreement with the first-order path to second order, a physical turning case, the
// deviation Jacobian, and clear failures.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <random>

#include "core/units.h"
#include "kinematics/error_state.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/inverse_kinematics.h"
#include "kinematics/simulate.h"

namespace tpcal::kinematics {
namespace {

MachineModel SimulatedMachine(MachineType t) {
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
  // Drawn z, y, x in sequence: the order GCC gave the constructor's arguments, which C++ leaves
  // unspecified (clang draws x first), so every compiler sees the same contact points.
  const double contact_z = 4 * u(rng), contact_y = 4 * u(rng), contact_x = 4 * u(rng);
  c.contact_in_tool_mm = Eigen::Vector3d(contact_x, contact_y, contact_z);
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
    const MachineModel m = SimulatedMachine(t);
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
    const MachineModel m = SimulatedMachine(t);
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
    const MachineModel m = SimulatedMachine(t);
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
  const MachineModel m = SimulatedMachine(MachineType::kAcTable);
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
    const MachineModel m = SimulatedMachine(t);
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

// Reference solve of S(u, v) = p0 + s n0, independent of the solver's chain shortcuts: Newton
// on ToolPointInPart (the plain chain, every error term evaluated at the iterate) with a
// central-difference Jacobian in (u, v), iterated until the step is below 1e-13 mm.
struct ReferenceSolution {
  double u = 0, v = 0, s = 0, residual_mm = 1e300;
};
ReferenceSolution ReferenceSolve(const MachineModel& m, const ErrorState& e, const CutPoint& c) {
  Workspace ws;
  auto S = [&](double u, double v) {
    return ToolPointInPart(m, e, Advance(Advance(c.axes, c.du.axes, u), c.dv.axes, v),
                           c.contact_in_tool_mm + u * c.du.contact_in_tool_mm + v * c.dv.contact_in_tool_mm, &ws);
  };
  ReferenceSolution r;
  r.u = r.v = r.s = 0.0;
  for (int it = 0; it < 100; ++it) {
    const double h = 1e-6;
    Eigen::Matrix3d J;
    J.col(0) = (S(r.u + h, r.v) - S(r.u - h, r.v)) / (2 * h);
    J.col(1) = (S(r.u, r.v + h) - S(r.u, r.v - h)) / (2 * h);
    J.col(2) = -c.nominal_normal;
    const Eigen::Vector3d F = S(r.u, r.v) - c.nominal_point_mm - r.s * c.nominal_normal;
    const Eigen::Vector3d step = -J.partialPivLu().solve(F);
    r.u += step(0), r.v += step(1), r.s += step(2);
    if (step.norm() < 1e-13) break;
  }
  r.residual_mm = (S(r.u, r.v) - c.nominal_point_mm - r.s * c.nominal_normal).norm();
  return r;
}

TEST(Simulate, ConvergesWhenTheErrorSlopeRivalsTheNetSweepSpeed) {
  // Cone flank of the NAS 979 piece (validation seed 11, rotary_positioning at 20x, point 16 of
  // CONE_2): ac_table at A = -5 deg, C = 90 deg, tool side touching the cone. Along the pass the
  // C table moves the point ~140 mm/rad and X moves -93 mm/rad: the net sweep speed |S_u| is
  // 34 mm/rad, so the slope of a large C positioning error (E_CC, harmonics 1 to 3 of up to
  // 40 mrad: ~0.1 rad/rad) is ~0.3 of it. Without the error slopes in the tangents the solve
  // contracted by 0.3 per step and stopped after 20 iterations (kNotConverged).
  // Truth: ReferenceSolve (plain chain, finite-difference Newton to 1e-13 mm); tolerance 1e-9 mm
  // on s and on the defining equation (the solver's own tolerance is 1e-10 mm on the step).
  const MachineModel m = SimulatedMachine(MachineType::kAcTable);
  CutPoint c;
  c.axes.y_mm = -48.380147906515909;
  c.axes.z_mm = 17.547411415090018;
  c.axes.a_rad = DegToRad(-5.0);
  c.axes.c_rad = DegToRad(90.0);
  c.axes.t_s = 37.749;
  c.contact_in_tool_mm = Eigen::Vector3d(0.0, 8.0, 16.717383979523671);
  c.du.axes = AxisDelta{-92.919130092288256, 0, 0, 0, 0, 2.9696155055325408};
  c.du.contact_in_tool_mm = Eigen::Vector3d(15.93911516447022, 0, 0);
  c.dv.contact_in_tool_mm = Eigen::Vector3d(0, 0, 1);  // along the tool axis
  c.nominal_point_mm = NominalToolPointInPart(m, c.axes, c.contact_in_tool_mm);
  auto S0 = [&](double a, double b) {
    return NominalToolPointInPart(m, Advance(Advance(c.axes, c.du.axes, a), c.dv.axes, b),
                                  c.contact_in_tool_mm + a * c.du.contact_in_tool_mm + b * c.dv.contact_in_tool_mm);
  };
  const double h = 1e-5;
  const Eigen::Vector3d su = (S0(h, 0) - S0(-h, 0)) / (2 * h), sv = (S0(0, h) - S0(0, -h)) / (2 * h);
  c.nominal_normal = su.cross(sv).normalized();
  ASSERT_NEAR(su.norm(), 34.0, 1.0);  // the net sweep speed the comment describes

  ErrorState e(m);
  ErrorTerm f;
  f.kind = TermKind::kFourier;
  f.label = "E_CC";
  f.quantity = Quantity::kAngle;
  f.effects = {{Axis::kC, Component::kRz, 1.0}};
  f.argument = Axis::kC;
  f.orders = {1, 1, 2, 2, 3, 3};
  f.is_sine = {false, true, false, true, false, true};
  f.coefficients = {2.5383e-3, 16.3347e-3, 2.3133e-3, 17.8616e-3, -10.8547e-3, 39.5007e-3};  // rad
  ASSERT_TRUE(e.AddTerm(m, f).ok());

  const ReferenceSolution ref = ReferenceSolve(m, e, c);
  ASSERT_LT(ref.residual_mm, 1e-10);
  ASSERT_GT(std::abs(ref.s), 1e-3);  // a real deviation (tens of um), not a trivial zero

  Workspace ws;
  Result<SurfacePoint> r = SimulateSurfacePoint(m, e, c, &ws);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_NEAR(r->deviation_mm, ref.s, 1e-9);
  EXPECT_NEAR(r->u, ref.u, 1e-9);
  EXPECT_NEAR(r->v, ref.v, 1e-9);
  const Eigen::Vector3d S = ToolPointInPart(m, e, Advance(Advance(c.axes, c.du.axes, r->u), c.dv.axes, r->v),
                                            c.contact_in_tool_mm + r->u * c.du.contact_in_tool_mm +
                                                r->v * c.dv.contact_in_tool_mm, &ws);
  EXPECT_LT((S - r->point_mm).norm(), 1e-9);
  EXPECT_LE(r->iterations, 10);  // Newton once the slow contraction is seen (was > 20)
}

TEST(Simulate, BadCutPointsFailClearly) {
  const MachineModel m = SimulatedMachine(MachineType::kAcTable);
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
