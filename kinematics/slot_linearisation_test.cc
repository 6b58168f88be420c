// Slot linearisation (kinematics/slot_linearisation.h) on its own, without test pieces: random
// consistent cut points on all four machine types, an error state with every catalog parameter
// and one term of each swept kind (polynomial, Fourier on every rotary axis, exponential drift).
// Truth: central finite differences of the forward model (SimulateSurfacePoint's deviation, um)
// per coefficient. Random draws from std::mt19937_64 with fixed seeds.
//
// Tolerances. The step h (display units) makes each point's deviation change by
// kSlotLinStep_um = 1e-2 um: h = 1e-2 / max(1, |J|). The forward model is solved to 1e-12 mm
// (1e-9 um) on the Newton step, so each deviation is rounded by at most ~1e-9 um. The central
// differences at h and h/2 are combined by Richardson's rule, (4 D(h/2) - D(h)) / 3, which cancels
// their h^2 truncation term: at a cut whose solve bends sharply that term alone reached 1.8e-3 of
// the entry (ac_table E_YX.c3 under another draw; it fell 100-fold with a 10-fold smaller step).
// Rounding of the combination: (4 * 2e-7 + 1e-7) / 3 = 3e-7 max(1, |J|). Allowed: 1e-6 (1 + |J|),
// three times that bound. Where the chain rule itself is exact (zero errors: the basis is taken exactly
// where the solve lands; constant terms at any errors: basis 1) that is the whole tolerance.
// Swept terms at realistic errors take the basis at the nominal instead of the solved sweep
// position, a relative change of order error / tangent speed (~1e-4): 1e-3 of each column's norm.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "core/status.h"
#include "core/units.h"
#include "kinematics/error_parameters.h"
#include "kinematics/error_state.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/identification.h"
#include "kinematics/machine_model.h"
#include "kinematics/simulate.h"
#include "kinematics/slot_linearisation.h"

namespace tpcal::kinematics {
namespace {

constexpr double kSlotLinStep_um = 1e-2;      // deviation change of one finite-difference step
constexpr double kSlotLinRounding = 1e-6;     // relative to 1 + |J| (see the top of the file)
constexpr double kSlotLinBasisShift = 1e-3;   // swept terms at realistic errors, of the column norm
constexpr int kSlotLinPoints = 12;            // cut points per machine type

const MachineType kSlotLinMachines[] = {MachineType::kAcTable, MachineType::kBcTable, MachineType::kBheadCtable,
                                        MachineType::kXyz};

MachineModel SlotLinMachine(MachineType t) {
  Result<MachineModel> m = MakeMachine(t);
  EXPECT_TRUE(m.ok()) << m.status().ToString();
  return *m;
}

// A random consistent cut: random state and contact, p0 = the nominal S(0, 0), a linear sweep
// and a rotary one (with a tool-frame contact increment), the normal perpendicular to both
// nominal sweep tangents (central differences).
CutPoint SlotLinRandomCut(const MachineModel& m, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> lin(-300.0, 300.0), rot(-3.0, 3.0), u(-1.0, 1.0);
  CutPoint c;
  c.axes.x_mm = lin(rng);
  c.axes.y_mm = lin(rng);
  c.axes.z_mm = lin(rng);
  c.axes.a_rad = m.HasAxis(Axis::kA) ? rot(rng) : 0.0;
  c.axes.b_rad = m.HasAxis(Axis::kB) ? rot(rng) : 0.0;
  c.axes.c_rad = m.HasAxis(Axis::kC) ? rot(rng) : 0.0;
  c.axes.t_s = 500.0 * (1.0 + u(rng));
  // Drawn z, y, x in sequence: the order GCC gave the constructor's arguments, which C++ leaves
  // unspecified (clang draws x first), so every compiler sees the same contact points.
  const double contact_z = 4 * u(rng), contact_y = 4 * u(rng), contact_x = 4 * u(rng);
  c.contact_in_tool_mm = Eigen::Vector3d(contact_x, contact_y, contact_z);
  c.nominal_point_mm = NominalToolPointInPart(m, c.axes, c.contact_in_tool_mm);
  c.du.axes = AxisDelta{u(rng), u(rng), u(rng), 0, 0, 0};
  c.dv.axes = AxisDelta{0, 0, 0, 0.002 * u(rng), 0.002 * u(rng), 0.004 * u(rng)};
  c.dv.contact_in_tool_mm = Eigen::Vector3d(0, 0, 0.5 * u(rng));
  auto S = [&](double a, double b) {
    return NominalToolPointInPart(m, Advance(Advance(c.axes, c.du.axes, a), c.dv.axes, b),
                                  c.contact_in_tool_mm + a * c.du.contact_in_tool_mm + b * c.dv.contact_in_tool_mm);
  };
  const double h = 1e-4;
  const Eigen::Vector3d su = (S(h, 0) - S(-h, 0)) / (2 * h), sv = (S(0, h) - S(0, -h)) / (2 * h);
  if (std::abs(su.normalized().dot(sv.normalized())) > 0.8) return SlotLinRandomCut(m, rng);  // redraw
  c.nominal_normal = (u(rng) > 0 ? 1.0 : -1.0) * su.cross(sv).normalized();
  return c;
}

std::vector<Observation> SlotLinObservations(const MachineModel& m, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Observation> obs;
  for (int i = 0; i < kSlotLinPoints; ++i) {
    Observation o;
    o.cut = SlotLinRandomCut(m, rng);
    o.measured_mm = o.cut.nominal_point_mm + 5e-3 * u(rng) * o.cut.nominal_normal;
    o.group = i % 3;
    obs.push_back(o);
  }
  return obs;
}

// Every catalog parameter (constant terms) at `scale` x +-20 um / urad, then the swept terms
// (their coefficients at `scale` times a few um): a straightness polynomial of X, a Fourier
// radial motion of every rotary axis and an exponential drift of X. `swept_from` receives the
// index of the first swept coefficient.
ErrorState SlotLinErrors(const MachineModel& m, double scale, std::mt19937_64& rng, int* swept_from) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ErrorState e(m);
  for (const ParameterInfo& p : ParameterCatalog(m))
    EXPECT_TRUE(e.SetParameter(m, p.name, scale * u(rng) * (p.quantity == Quantity::kLength ? 20e-3 : 20e-6)).ok())
        << p.name;
  *swept_from = e.num_coefficients();
  ErrorTerm poly;
  poly.kind = TermKind::kPolynomial;
  poly.label = "E_YX";
  poly.effects = {{Axis::kX, Component::kTy, 1.0}};
  poly.argument = Axis::kX;
  poly.powers = {2, 3};
  poly.coefficients = {scale * u(rng) * 5e-3 / 9e4, scale * u(rng) * 5e-3 / 2.7e7};  // ~5 um at 300 mm
  EXPECT_TRUE(e.AddTerm(m, poly).ok());
  for (const AxisLink& l : m.links) {
    if (!IsRotary(l.axis)) continue;
    ErrorTerm f;
    f.kind = TermKind::kFourier;
    f.label = std::string("E_X") + AxisLetter(l.axis);
    f.effects = {{l.axis, Component::kTx, 1.0}};
    f.argument = l.axis;
    f.orders = {2, 3};
    f.is_sine = {false, true};
    f.coefficients = {scale * u(rng) * 3e-3, scale * u(rng) * 3e-3};
    EXPECT_TRUE(e.AddTerm(m, f).ok());
  }
  ErrorTerm drift;
  drift.kind = TermKind::kExponentialDrift;
  drift.label = "E_X0X";
  drift.effects = {{Axis::kX, Component::kTx, 1.0}};
  drift.tau_s = 600;
  drift.coefficients = {scale * u(rng) * 8e-3};
  EXPECT_TRUE(e.AddTerm(m, drift).ok());
  return e;
}

// d deviation (um) / d coefficient (display units) at every observation by central differences
// of SimulateSurfacePoint (solved to 1e-12 mm), step per point as at the top of the file.
Eigen::MatrixXd SlotLinCentralDifferences(const MachineModel& m, ErrorState e, const std::vector<int>& coefficients,
                                          const std::vector<Observation>& obs, const Eigen::MatrixXd& J) {
  SimulateOptions tight;
  tight.tolerance_mm = 1e-12;
  Workspace ws;
  Eigen::MatrixXd fd(J.rows(), J.cols());
  for (std::size_t j = 0; j < coefficients.size(); ++j) {
    const int c = coefficients[j];
    const double x0 = e.coefficient(c);
    const double per = e.coefficient_info(c).display_per_internal;
    for (std::size_t i = 0; i < obs.size(); ++i) {
      const auto ii = static_cast<Eigen::Index>(i), jj = static_cast<Eigen::Index>(j);
      const double h_display = kSlotLinStep_um / std::max(1.0, std::abs(J(ii, jj)));
      auto deviation_um = [&](double value) {
        e.set_coefficient(c, value);
        Result<SurfacePoint> s = SimulateSurfacePoint(m, e, obs[i].cut, &ws, tight);
        EXPECT_TRUE(s.ok()) << s.status().ToString();
        return s.ok() ? MmToUm(s->deviation_mm) : 0.0;
      };
      auto central = [&](double h) { return (deviation_um(x0 + h / per) - deviation_um(x0 - h / per)) / (2.0 * h); };
      const double d_h = central(h_display), d_half = central(0.5 * h_display);
      e.set_coefficient(c, x0);
      fd(ii, jj) = (4.0 * d_half - d_h) / 3.0;  // Richardson: the h^2 truncation term cancels
    }
  }
  return fd;
}

std::vector<int> SlotLinRange(int begin, int end) {
  std::vector<int> v;
  for (int c = begin; c < end; ++c) v.push_back(c);
  return v;
}

// Every entry within the rounding tolerance of the finite differences.
void SlotLinExpectEntriesMatch(const Eigen::MatrixXd& J, const Eigen::MatrixXd& fd, const ErrorState& e,
                               const std::vector<int>& coefficients, MachineType t) {
  for (Eigen::Index j = 0; j < J.cols(); ++j)
    for (Eigen::Index i = 0; i < J.rows(); ++i)
      EXPECT_NEAR(J(i, j), fd(i, j), kSlotLinRounding * (1.0 + std::abs(fd(i, j))))
          << MachineTypeName(t) << " " << e.coefficient_info(coefficients[static_cast<std::size_t>(j)]).name
          << " point " << i;
}

TEST(SlotLinearisation, SlotsOfListsEachWrittenSlotOnceInFirstUseOrder) {
  const MachineModel m = SlotLinMachine(MachineType::kAcTable);
  std::mt19937_64 rng(11);
  int swept_from = 0;
  const ErrorState e = SlotLinErrors(m, 0.0, rng, &swept_from);
  // The polynomial's two coefficients write one slot (X, ty); the drift writes (X, tx).
  const std::vector<int> poly_and_drift = {swept_from, swept_from + 1, e.num_coefficients() - 1};
  const std::vector<ErrorSlot> slots = SlotsOf(e, poly_and_drift);
  ASSERT_EQ(slots.size(), 2u);
  EXPECT_EQ(slots[0], (ErrorSlot{Axis::kX, Component::kTy}));
  EXPECT_EQ(slots[1], (ErrorSlot{Axis::kX, Component::kTx}));
  std::vector<ErrorSlot> merged = {ErrorSlot{Axis::kX, Component::kTx}};
  AddSlots(slots, &merged);
  ASSERT_EQ(merged.size(), 2u);
  EXPECT_EQ(merged[0], (ErrorSlot{Axis::kX, Component::kTx}));
  EXPECT_EQ(merged[1], (ErrorSlot{Axis::kX, Component::kTy}));
}

// Zero errors, every coefficient: the chain rule is exact, so every entry matches.
TEST(SlotLinearisation, ColumnsMatchCentralDifferencesAtZeroErrors) {
  std::mt19937_64 rng(2024);
  for (MachineType t : kSlotLinMachines) {
    const MachineModel m = SlotLinMachine(t);
    int swept_from = 0;
    const ErrorState e = SlotLinErrors(m, 0.0, rng, &swept_from);
    const std::vector<Observation> obs = SlotLinObservations(m, rng);
    const std::vector<int> all = SlotLinRange(0, e.num_coefficients());
    Result<LinearDesign> lin = LineariseBySlots(m, e, all, obs);
    ASSERT_TRUE(lin.ok()) << lin.status().ToString();
    ASSERT_EQ(lin->J_dev_params.cols(), static_cast<Eigen::Index>(all.size()));
    const Eigen::MatrixXd fd = SlotLinCentralDifferences(m, e, all, obs, lin->J_dev_params);
    SlotLinExpectEntriesMatch(lin->J_dev_params, fd, e, all, t);
  }
}

// Realistic errors (+-20 um / urad and swept terms of a few um): the constant terms' columns
// (basis 1) are still exact; the swept terms' within the basis shift of each column's norm.
TEST(SlotLinearisation, ColumnsMatchCentralDifferencesAtRealisticErrors) {
  std::mt19937_64 rng(77);
  for (MachineType t : kSlotLinMachines) {
    const MachineModel m = SlotLinMachine(t);
    int swept_from = 0;
    const ErrorState e = SlotLinErrors(m, 1.0, rng, &swept_from);
    const std::vector<Observation> obs = SlotLinObservations(m, rng);
    const std::vector<int> constant = SlotLinRange(0, swept_from);
    const std::vector<int> swept = SlotLinRange(swept_from, e.num_coefficients());
    Result<LinearDesign> lin_c = LineariseBySlots(m, e, constant, obs);
    ASSERT_TRUE(lin_c.ok()) << lin_c.status().ToString();
    SlotLinExpectEntriesMatch(lin_c->J_dev_params, SlotLinCentralDifferences(m, e, constant, obs, lin_c->J_dev_params),
                              e, constant, t);
    Result<LinearDesign> lin_s = LineariseBySlots(m, e, swept, obs);
    ASSERT_TRUE(lin_s.ok()) << lin_s.status().ToString();
    const Eigen::MatrixXd fd = SlotLinCentralDifferences(m, e, swept, obs, lin_s->J_dev_params);
    for (Eigen::Index j = 0; j < fd.cols(); ++j) {
      const double norm = fd.col(j).norm();
      EXPECT_LE((lin_s->J_dev_params.col(j) - fd.col(j)).norm(),
                kSlotLinBasisShift * norm + kSlotLinRounding * (1.0 + norm) * std::sqrt(static_cast<double>(fd.rows())))
          << MachineTypeName(t) << " " << e.coefficient_info(swept[static_cast<std::size_t>(j)]).name;
    }
  }
}

// The design's deviations are the forward model's: predicted = SimulateSurfacePoint's deviation,
// measured = n0 . (m - p0), both in um; the coefficient columns from a shared slot design equal
// LineariseBySlots' (one design serves any coefficients writing its slots).
TEST(SlotLinearisation, SharedSlotDesignGivesTheForwardModelAndTheSameColumns) {
  std::mt19937_64 rng(5);
  const MachineModel m = SlotLinMachine(MachineType::kAcTable);
  int swept_from = 0;
  const ErrorState e = SlotLinErrors(m, 1.0, rng, &swept_from);
  const std::vector<Observation> obs = SlotLinObservations(m, rng);
  const std::vector<int> all = SlotLinRange(0, e.num_coefficients());
  Result<SlotDesign> design = LineariseSlots(m, e, SlotsOf(e, all), obs);
  ASSERT_TRUE(design.ok()) << design.status().ToString();
  EXPECT_EQ(design->lin.J_dev_params.cols(), 0);
  ASSERT_EQ(design->dslot_um.rows(), static_cast<Eigen::Index>(obs.size()));
  Workspace ws;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    Result<SurfacePoint> s = SimulateSurfacePoint(m, e, obs[i].cut, &ws);
    ASSERT_TRUE(s.ok());
    const auto ii = static_cast<Eigen::Index>(i);
    EXPECT_NEAR(design->lin.predicted_dev_um(ii), MmToUm(s->deviation_mm), 1e-9);
    EXPECT_NEAR(design->lin.measured_dev_um(ii),
                MmToUm(obs[i].cut.nominal_normal.dot(obs[i].measured_mm - obs[i].cut.nominal_point_mm)), 1e-9);
  }
  const std::vector<int> swept = SlotLinRange(swept_from, e.num_coefficients());
  Result<Eigen::MatrixXd> shared = CoefficientColumns(*design, e, swept, obs);
  ASSERT_TRUE(shared.ok()) << shared.status().ToString();
  Result<LinearDesign> own = LineariseBySlots(m, e, swept, obs);
  ASSERT_TRUE(own.ok());
  EXPECT_LE((*shared - own->J_dev_params).norm(), 1e-12 * (1.0 + own->J_dev_params.norm()));
}

TEST(SlotLinearisation, CoefficientColumnsRejectsAMismatchedDesign) {
  std::mt19937_64 rng(9);
  const MachineModel m = SlotLinMachine(MachineType::kAcTable);
  int swept_from = 0;
  const ErrorState e = SlotLinErrors(m, 0.0, rng, &swept_from);
  const std::vector<Observation> obs = SlotLinObservations(m, rng);
  // A design holding only the polynomial's slot: the drift writes a slot it lacks.
  Result<SlotDesign> design = LineariseSlots(m, e, SlotsOf(e, {swept_from}), obs);
  ASSERT_TRUE(design.ok());
  Result<Eigen::MatrixXd> lacks = CoefficientColumns(*design, e, {e.num_coefficients() - 1}, obs);
  ASSERT_FALSE(lacks.ok());
  EXPECT_EQ(lacks.status().code(), StatusCode::kInvalidArgument);
  const std::vector<Observation> fewer(obs.begin(), obs.end() - 1);
  Result<Eigen::MatrixXd> rows = CoefficientColumns(*design, e, {swept_from}, fewer);
  ASSERT_FALSE(rows.ok());
  EXPECT_EQ(rows.status().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace tpcal::kinematics
