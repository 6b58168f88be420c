// Jacobians of the tool point and pose with respect to every kind of error coefficient, by
// automatic differentiation, against central finite differences, in three regimes (zero, tiny,
// random realistic, plus large to exercise the non-linear chain), on all four machine types.
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "core/units.h"
#include "kinematics/chain_eval.h"
#include "kinematics/error_parameters.h"
#include "kinematics/error_state.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/jacobians.h"

namespace tpcal::kinematics {
namespace {

// A rich error state: every catalog parameter, plus one term of each kind, values scaled by
// `scale` (1 = 10 um / 10 urad class).
ErrorState RichErrors(const MachineModel& m, double scale, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto val = [&](Quantity q) { return scale * u(rng) * (q == Quantity::kLength ? 10e-3 : 10e-6); };
  ErrorState e(m);
  for (const ParameterInfo& p : ParameterCatalog(m)) {
    // Aliases of squareness (beta_ZX) are the same parameter; the catalog lists each once.
    EXPECT_TRUE(e.SetParameter(m, p.name, val(p.quantity)).ok()) << p.name;
  }
  ErrorTerm poly;
  poly.kind = TermKind::kPolynomial;
  poly.label = "E_YX";
  poly.effects = {{Axis::kX, Component::kTy, 1.0}};
  poly.argument = Axis::kX;
  poly.powers = {1, 2, 3};
  poly.coefficients = {val(Quantity::kLength) / 100, val(Quantity::kLength) / 1e4, val(Quantity::kLength) / 1e6};
  EXPECT_TRUE(e.AddTerm(m, poly).ok());
  ErrorTerm pitch = poly;
  pitch.label = "E_BZ";
  pitch.quantity = Quantity::kAngle;
  pitch.effects = {{Axis::kZ, Component::kRy, 1.0}};
  pitch.argument = Axis::kZ;
  pitch.powers = {0, 1};
  pitch.coefficients = {val(Quantity::kAngle), val(Quantity::kAngle) / 100};
  EXPECT_TRUE(e.AddTerm(m, pitch).ok());
  for (const AxisLink& l : m.links) {
    if (!IsRotary(l.axis)) continue;
    const std::string k(1, AxisLetter(l.axis));
    ErrorTerm f;
    f.kind = TermKind::kFourier;
    f.label = "E_X" + k;
    f.effects = {{l.axis, Component::kTx, 1.0}};
    f.argument = l.axis;
    f.orders = {1, 2, 2, 3};
    f.is_sine = {true, false, true, false};
    for (int i = 0; i < 4; ++i) f.coefficients.push_back(val(Quantity::kLength));
    EXPECT_TRUE(e.AddTerm(m, f).ok());
    ErrorTerm t;
    t.kind = TermKind::kTable;
    t.label = "E_" + k + k;
    t.quantity = Quantity::kAngle;
    t.effects = {{l.axis, static_cast<Component>(AxisIndex(l.axis)), 1.0}};
    t.argument = l.axis;
    t.nodes = {0.0, 1.0, 2.5, 4.0, 5.5};
    t.periodic = true;
    t.interpolation = Interpolation::kCubic;
    for (int i = 0; i < 5; ++i) t.coefficients.push_back(val(Quantity::kAngle));
    EXPECT_TRUE(e.AddTerm(m, t).ok());
    ErrorTerm t2;
    t2.kind = TermKind::kTable;
    t2.label = "E_A" + k;
    t2.quantity = Quantity::kAngle;
    t2.effects = {{l.axis, Component::kRx, 1.0}};
    t2.argument = l.axis;
    t2.nodes = {-2.0, 0.0, 2.0};
    t2.second_argument = Axis::kZ;
    t2.second_nodes = {-100.0, 300.0};
    for (int i = 0; i < 6; ++i) t2.coefficients.push_back(val(Quantity::kAngle));
    EXPECT_TRUE(e.AddTerm(m, t2).ok());
    ErrorTerm d;
    d.kind = TermKind::kExponentialDrift;
    d.label = "E_Y0" + k;
    d.effects = {{l.axis, Component::kTy, 1.0}};
    d.tau_s = 900;
    d.coefficients = {val(Quantity::kLength)};
    EXPECT_TRUE(e.AddTerm(m, d).ok());
    ErrorTerm r = d;
    r.kind = TermKind::kLinearDrift;
    r.label = "E_B0" + k;
    r.quantity = Quantity::kAngle;
    r.effects = {{l.axis, Component::kRy, 1.0}};
    r.t0_s = 100;
    r.coefficients = {val(Quantity::kAngle) / 3600};
    EXPECT_TRUE(e.AddTerm(m, r).ok());
  }
  ErrorTerm op;
  op.kind = TermKind::kOperationOffset;
  op.label = "E_Z0Z";
  op.effects = {{Axis::kZ, Component::kTz, 1.0}};
  op.op = 2;
  op.coefficients = {val(Quantity::kLength)};
  EXPECT_TRUE(e.AddTerm(m, op).ok());
  return e;
}

AxisState RandomState(const MachineModel& m, std::mt19937_64& rng, int trial) {
  std::uniform_real_distribution<double> lin(-400.0, 400.0), rot(-3.1, 3.1), time(0.0, 3600.0);
  AxisState s;
  s.x_mm = lin(rng); s.y_mm = lin(rng); s.z_mm = lin(rng);
  s.a_rad = rot(rng); s.b_rad = rot(rng); s.c_rad = rot(rng);
  if (m.type == MachineType::kAcTable) {  // exercise the seed 002 conditional parameters
    if (trial % 3 == 0) s.a_rad = 0.0;
    if (trial % 3 == 1) s.a_rad = DegToRad(-90.0);
  }
  s.t_s = time(rng);
  s.op = 1 + trial % 3;
  return s;
}

Eigen::Vector3d RotationVector(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

void CheckRegime(MachineType type, double scale, uint64_t seed) {
  std::mt19937_64 rng(seed);
  Result<MachineModel> mm = MakeMachine(type);
  ASSERT_TRUE(mm.ok());
  MachineModel m = *mm;
  std::uniform_real_distribution<double> piv(-150.0, 150.0);
  for (AxisLink& l : m.links) {
    if (IsRotary(l.axis)) l.pivot_mm += Eigen::Vector3d{piv(rng), piv(rng), piv(rng)};
  }
  ErrorState e = RichErrors(m, scale, rng);
  const ActiveSet all = AllCoefficients(e);
  Workspace ws;
  const Eigen::Vector3d contact(3.0, -4.0, 12.0);
  for (int trial = 0; trial < 12; ++trial) {
    const AxisState s = RandomState(m, rng, trial);
    Eigen::Matrix<double, 3, Eigen::Dynamic> J;
    const Eigen::Vector3d p = ToolPointJacobian(m, e, all, s, contact, &J);
    // The templated chain at the current values reproduces the double chain.
    EXPECT_LT((p - ToolPointInPart(m, e, s, contact, &ws)).norm(), 1e-10);
    Eigen::Matrix<double, 6, Eigen::Dynamic> Jpose;
    PartFromToolJacobian(m, e, all, s, &Jpose);
    for (int j = 0; j < all.size(); ++j) {
      const int i = all.coefficients[j];
      const double x0 = e.coefficient(i);
      // Step: 1e-5 mm of tool motion at most; roundoff of the central difference ~1e-8 |J|,
      // truncation ~h^2 |f'''| far below that. Tolerance 1e-6 (1 + |J|).
      const double h = 1e-5 / std::max(1.0, J.col(j).norm() + Jpose.col(j).norm());
      e.set_coefficient(i, x0 + h);
      const Rigid3 tp = PartFromTool(m, e, s, &ws);
      e.set_coefficient(i, x0 - h);
      const Rigid3 tm = PartFromTool(m, e, s, &ws);
      e.set_coefficient(i, x0);
      const Eigen::Vector3d fd = (tp * contact - tm * contact) / (2 * h);
      const double tol = 1e-6 * (1.0 + J.col(j).norm());
      EXPECT_LT((fd - J.col(j)).norm(), tol)
          << MachineTypeName(type) << " scale " << scale << " " << e.coefficient_info(i).name;
      const Eigen::Vector3d fd_t = (tp.translation() - tm.translation()) / (2 * h);
      // Rotation: its own step, since a rotation matrix carries ~1e-16 of rounding whatever h.
      const double hw = 1e-6 / std::max(1.0, Jpose.col(j).tail<3>().norm());
      e.set_coefficient(i, x0 + hw);
      const Eigen::Matrix3d rp = PartFromTool(m, e, s, &ws).linear();
      e.set_coefficient(i, x0 - hw);
      const Eigen::Matrix3d rm = PartFromTool(m, e, s, &ws).linear();
      e.set_coefficient(i, x0);
      const Eigen::Vector3d fd_w = RotationVector(rp * rm.transpose()) / (2 * hw);
      EXPECT_LT((fd_t - Jpose.col(j).head<3>()).norm(), 1e-6 * (1.0 + Jpose.col(j).head<3>().norm()))
          << e.coefficient_info(i).name;
      EXPECT_LT((fd_w - Jpose.col(j).tail<3>()).norm(), 1e-6 * (1.0 + Jpose.col(j).tail<3>().norm()))
          << e.coefficient_info(i).name;
    }
  }
}

TEST(Jacobian, MatchesCentralDifferencesZeroErrors) {
  for (MachineType t : {MachineType::kAcTable, MachineType::kBcTable, MachineType::kBheadCtable, MachineType::kXyz}) {
    CheckRegime(t, 0.0, 11);
  }
}
TEST(Jacobian, MatchesCentralDifferencesTinyErrors) {
  for (MachineType t : {MachineType::kAcTable, MachineType::kBcTable, MachineType::kBheadCtable, MachineType::kXyz}) {
    CheckRegime(t, 1e-6, 12);
  }
}
TEST(Jacobian, MatchesCentralDifferencesRandomErrors) {
  for (MachineType t : {MachineType::kAcTable, MachineType::kBcTable, MachineType::kBheadCtable, MachineType::kXyz}) {
    CheckRegime(t, 1.0, 13);
  }
}
TEST(Jacobian, MatchesCentralDifferencesLargeErrors) {
  // 1000 x realistic (10 mm, 10 mrad): the chain is far from linear; AD stays exact.
  for (MachineType t : {MachineType::kAcTable, MachineType::kBcTable, MachineType::kBheadCtable, MachineType::kXyz}) {
    CheckRegime(t, 1000.0, 14);
  }
}

// ToolPointJacobian composes the double chain with one Jet pass per link; forward-mode
// differentiation of the whole chain (ToolPointInPartT with Jets seeded on the coefficients)
// gives the same derivative by other operations. Truth: equal up to rounding. Tolerance:
// 1e-16 relative per operation over a chain of ~10 products with lever arms up to ~1e3 mm:
// 1e-11 (1 + |J|), four orders above the rounding and four below the finite-difference tests'.
TEST(Jacobian, EqualsForwardModeThroughTheWholeChain) {
  using Jet8 = ceres::Jet<double, 8>;
  for (MachineType type : {MachineType::kAcTable, MachineType::kBcTable, MachineType::kBheadCtable, MachineType::kXyz}) {
    for (double scale : {0.0, 1.0, 1000.0}) {
      std::mt19937_64 rng(21);
      Result<MachineModel> m = MakeMachine(type);
      ASSERT_TRUE(m.ok());
      const ErrorState e = RichErrors(*m, scale, rng);
      const ActiveSet all = AllCoefficients(e);
      const Eigen::Vector3d contact(3.0, -4.0, 12.0);
      for (int trial = 0; trial < 6; ++trial) {
        const AxisState s = RandomState(*m, rng, trial);
        Eigen::Matrix<double, 3, Eigen::Dynamic> J;
        ToolPointJacobian(*m, e, all, s, contact, &J);
        ChainScratch scratch;
        for (int begin = 0; begin < all.size(); begin += 8) {
          std::vector<Jet8> x(static_cast<std::size_t>(all.size()));
          for (int j = 0; j < all.size(); ++j) {
            x[static_cast<std::size_t>(j)] = Jet8(e.coefficient(all.coefficients[static_cast<std::size_t>(j)]));
            if (j >= begin && j < begin + 8) x[static_cast<std::size_t>(j)].v[j - begin] = 1.0;
          }
          const Eigen::Matrix<Jet8, 3, 1> p = ToolPointInPartT<Jet8>(*m, e, all, x.data(), s, contact, &scratch);
          for (int j = begin; j < std::min(begin + 8, all.size()); ++j) {
            Eigen::Vector3d fwd;
            for (int r = 0; r < 3; ++r) fwd(r) = p(r).v[j - begin];
            EXPECT_LT((fwd - J.col(j)).norm(), 1e-11 * (1.0 + fwd.norm()))
                << MachineTypeName(type) << " scale " << scale << " "
                << e.coefficient_info(all.coefficients[static_cast<std::size_t>(j)]).name;
          }
        }
      }
    }
  }
}

// A slot column is the column of a coefficient that writes only that slot with gain 1 and basis
// value 1 (a power-0 polynomial term added at zero). Truth: the same derivative by the same
// operations; tolerance 1e-12 (1 + |J|) (rounding only). Every component of every link, at
// random realistic errors, on all four machine types.
TEST(Jacobian, SlotColumnsEqualUnitCoefficientColumns) {
  for (MachineType type : {MachineType::kAcTable, MachineType::kBcTable, MachineType::kBheadCtable, MachineType::kXyz}) {
    std::mt19937_64 rng(31);
    Result<MachineModel> m = MakeMachine(type);
    ASSERT_TRUE(m.ok());
    ErrorState e = RichErrors(*m, 1.0, rng);
    std::vector<ErrorSlot> slots;
    std::vector<std::string> names;
    for (const AxisLink& l : m->links)
      for (int c = 0; c < kNumComponents; ++c) {
        if (!IsRotary(l.axis) && c >= 6 && c < 9) continue;  // line offsets exist on rotary links only
        slots.push_back({l.axis, static_cast<Component>(c)});
        ErrorTerm t;
        t.kind = TermKind::kPolynomial;
        t.label = "slot_" + std::to_string(slots.size());
        t.quantity = IsAngular(static_cast<Component>(c)) ? Quantity::kAngle : Quantity::kLength;
        t.effects = {{l.axis, static_cast<Component>(c), 1.0}};
        t.argument = Axis::kX;
        t.powers = {0};
        t.coefficients = {0.0};
        ASSERT_TRUE(e.AddTerm(*m, t).ok());
        names.push_back(e.coefficient_info(e.num_coefficients() - 1).name);
      }
    auto active = SelectCoefficients(e, names);
    ASSERT_TRUE(active.ok());
    for (int trial = 0; trial < 6; ++trial) {
      const AxisState s = RandomState(*m, rng, trial);
      const Eigen::Vector3d contact(3.0, -4.0, 12.0);
      Eigen::Matrix<double, 3, Eigen::Dynamic> J_coef, J_slot;
      const Eigen::Vector3d p = ToolPointJacobian(*m, e, *active, s, contact, &J_coef);
      const Eigen::Vector3d ps = ToolPointSlotJacobian(*m, e, s, contact, slots, &J_slot);
      EXPECT_LT((p - ps).norm(), 1e-12 * (1.0 + p.norm()));
      ASSERT_EQ(J_slot.cols(), static_cast<Eigen::Index>(slots.size()));
      for (std::size_t k = 0; k < slots.size(); ++k) {
        const Eigen::Index j = static_cast<Eigen::Index>(k);
        EXPECT_LT((J_slot.col(j) - J_coef.col(j)).norm(), 1e-12 * (1.0 + J_coef.col(j).norm()))
            << MachineTypeName(type) << " " << AxisLetter(slots[k].axis) << " " << ComponentName(slots[k].component);
      }
    }
  }
}

// The Jet fast paths of chain_eval.h (a rotation or axis tilt skipped when its components have
// zero value and no derivative, a linear link as a pure translation, a rotary axis rotation in
// double when it carries no derivative): a sparse error state where most link components are
// exactly zero, some active coefficients at zero value (a zero value with a derivative must not
// be skipped), some inactive ones non-zero. The Jacobian must match central differences and the
// columns of the same coefficients with every catalog parameter active (no component skipped).
void CheckSparse(MachineType type, uint64_t seed) {
  std::mt19937_64 rng(seed);
  Result<MachineModel> mm = MakeMachine(type);
  ASSERT_TRUE(mm.ok());
  const MachineModel& m = *mm;
  const std::vector<ParameterInfo> catalog = ParameterCatalog(m);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ErrorState e(m);
  std::vector<std::string> active_names, all_names;
  for (std::size_t k = 0; k < catalog.size(); ++k) {
    const ParameterInfo& p = catalog[k];
    const double v = u(rng) * (p.quantity == Quantity::kLength ? 10e-3 : 10e-6);
    // k % 4: 0 active at zero, 1 active non-zero, 2 inactive non-zero, 3 inactive zero.
    ASSERT_TRUE(e.SetParameter(m, p.name, k % 4 == 1 || k % 4 == 2 ? v : 0.0).ok()) << p.name;
    all_names.push_back(p.name);
    if (k % 4 <= 1) active_names.push_back(p.name);
  }
  Result<ActiveSet> active = SelectCoefficients(e, active_names);
  ASSERT_TRUE(active.ok()) << active.status().ToString();
  Result<ActiveSet> all = SelectCoefficients(e, all_names);
  ASSERT_TRUE(all.ok()) << all.status().ToString();
  Workspace ws;
  const Eigen::Vector3d contact(3.0, -4.0, 12.0);
  for (int trial = 0; trial < 12; ++trial) {
    const AxisState s = RandomState(m, rng, trial);
    Eigen::Matrix<double, 3, Eigen::Dynamic> J, J_all;
    const Eigen::Vector3d p = ToolPointJacobian(m, e, *active, s, contact, &J);
    ToolPointJacobian(m, e, *all, s, contact, &J_all);
    EXPECT_LT((p - ToolPointInPart(m, e, s, contact, &ws)).norm(), 1e-10);
    for (int j = 0; j < active->size(); ++j) {
      const int i = active->coefficients[j];
      const std::string& name = e.coefficient_info(i).name;
      int j_all = -1;
      for (int k = 0; k < all->size(); ++k)
        if (all->coefficients[k] == i) j_all = k;
      ASSERT_GE(j_all, 0) << name;
      // Same derivative through the full Jet chain: equal to rounding.
      EXPECT_LT((J.col(j) - J_all.col(j_all)).norm(), 1e-12 * (1.0 + J_all.col(j_all).norm()))
          << MachineTypeName(type) << " " << name;
      const double x0 = e.coefficient(i);
      const double h = 1e-5 / std::max(1.0, J.col(j).norm());
      e.set_coefficient(i, x0 + h);
      const Eigen::Vector3d pp = ToolPointInPart(m, e, s, contact, &ws);
      e.set_coefficient(i, x0 - h);
      const Eigen::Vector3d pm = ToolPointInPart(m, e, s, contact, &ws);
      e.set_coefficient(i, x0);
      const Eigen::Vector3d fd = (pp - pm) / (2 * h);
      EXPECT_LT((fd - J.col(j)).norm(), 1e-6 * (1.0 + J.col(j).norm()))
          << MachineTypeName(type) << " " << name;
    }
  }
}

TEST(Jacobian, SparseErrorsFastPathsMatchCentralDifferences) {
  for (MachineType t : {MachineType::kAcTable, MachineType::kBcTable, MachineType::kBheadCtable, MachineType::kXyz}) {
    CheckSparse(t, 15);
  }
}

TEST(Jacobian, InactiveConditionGivesZeroColumn) {
  Result<MachineModel> m = MakeMachine(MachineType::kAcTable);
  ASSERT_TRUE(m.ok());
  ErrorState e(*m);
  ASSERT_TRUE(e.SetParameter(*m, "dx_CR(0)", 0.0).ok());
  ASSERT_TRUE(e.SetParameter(*m, "dz_AR(-90)", 0.0).ok());
  Result<ActiveSet> a = SelectCoefficients(e, {"dx_CR(0)", "dz_AR(-90)"});
  ASSERT_TRUE(a.ok());
  AxisState s;
  s.x_mm = 140;
  s.c_rad = 1.0;
  Eigen::Matrix<double, 3, Eigen::Dynamic> J;
  ToolPointJacobian(*m, e, *a, s, Eigen::Vector3d::Zero(), &J);
  EXPECT_GT(J.col(0).norm(), 0.5);       // (I - RotZ(1 rad)) x: about 0.96
  EXPECT_EQ(J.col(1).norm(), 0.0);       // A = 0: the A = -90 parameter does not act
}

}  // namespace
}  // namespace tpcal::kinematics

namespace tpcal::kinematics {
namespace {

TEST(ActiveSets, StandardSetsActivateFromZeroErrors) {
  for (MachineType t : {MachineType::kAcTable, MachineType::kBcTable, MachineType::kBheadCtable, MachineType::kXyz}) {
    Result<MachineModel> m = MakeMachine(t);
    ASSERT_TRUE(m.ok());
    ErrorState e(*m);
    Result<ActiveSet> iso = ActivateParameters(*m, &e, IsoLocationSet(*m));
    ASSERT_TRUE(iso.ok()) << iso.status().ToString();
    EXPECT_EQ(iso->size(), static_cast<int>(IsoLocationSet(*m).size()));
    if (t == MachineType::kBcTable) {
      EXPECT_EQ(iso->size(), 11);  // seed 001
    }
    if (t == MachineType::kAcTable) {
      ErrorState s(*m);
      Result<ActiveSet> s2 = ActivateParameters(*m, &s, Seed002Set(*m));
      ASSERT_TRUE(s2.ok()) << s2.status().ToString();
      EXPECT_EQ(s2->size(), 11);
      // beta_ZX is found through its alias of E_B(0X)Z.
      EXPECT_EQ(s.coefficient_info(s2->coefficients[9]).name, "E_B(0X)Z");
    }
    EXPECT_FALSE(ActivateParameters(*m, &e, {"E_Q0Q"}).ok());
  }
}

TEST(ActiveSets, AnUnknownNameListsTheKnownOnesBounded) {
  Result<MachineModel> m = MakeMachine(MachineType::kAcTable);
  ASSERT_TRUE(m.ok());
  ErrorState e(*m);
  Result<ActiveSet> bad = ActivateParameters(*m, &e, {"E_X0A", "NOPE"});
  ASSERT_FALSE(bad.ok());
  const std::string message = bad.status().message();
  EXPECT_EQ(message.rfind("unknown parameter 'NOPE'; expected one of the " +
                              std::to_string(ParameterCatalog(*m).size()) + " parameters of the ac_table machine (E_X0A, ",
                          0),
            0u)
      << message;
  EXPECT_NE(message.find("...; every one in kinematics/errors_yaml.md"), std::string::npos) << message;
  EXPECT_EQ(message.find("gamma_CR(-90)"), std::string::npos) << "listed beyond the bound: " << message;
  // A power beyond the polynomial's names the parameter, not a generated text.
  Result<ActiveSet> power = ActivateParameters(*m, &e, {"E_ZX.c99"});
  ASSERT_FALSE(power.ok());
  EXPECT_TRUE(power.status().file().empty()) << power.status().ToString();
  EXPECT_EQ(power.status().message().rfind("parameters of E_ZX (powers 99): ", 0), 0u) << power.status().message();
}

}  // namespace
}  // namespace tpcal::kinematics
