// The library chain against an independent, straightforward composition of 4x4 homogeneous
// matrices written here from the formulas in conventions.h (no library kinematics code used):
// all four machine types, random pivots, random large errors in every component (exactness is
// checked, not a linearisation), random axis positions.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "kinematics/forward_kinematics.h"
#include "kinematics/error_parameters.h"
#include "kinematics/error_state.h"
#include "kinematics/machine_model.h"

namespace tpcal::kinematics {
namespace {

using M4 = Eigen::Matrix4d;

M4 Tr(double x, double y, double z) {
  M4 m = M4::Identity();
  m(0, 3) = x;
  m(1, 3) = y;
  m(2, 3) = z;
  return m;
}
M4 Tr(const Eigen::Vector3d& v) { return Tr(v.x(), v.y(), v.z()); }
M4 D4(double a) {  // about X
  M4 m = M4::Identity();
  m(1, 1) = std::cos(a); m(1, 2) = -std::sin(a);
  m(2, 1) = std::sin(a); m(2, 2) = std::cos(a);
  return m;
}
M4 D5(double b) {  // about Y
  M4 m = M4::Identity();
  m(0, 0) = std::cos(b); m(0, 2) = std::sin(b);
  m(2, 0) = -std::sin(b); m(2, 2) = std::cos(b);
  return m;
}
M4 D6(double c) {  // about Z
  M4 m = M4::Identity();
  m(0, 0) = std::cos(c); m(0, 1) = -std::sin(c);
  m(1, 0) = std::sin(c); m(1, 1) = std::cos(c);
  return m;
}
M4 RotAbout(int dir, double a) { return dir == 0 ? D4(a) : dir == 1 ? D5(a) : D6(a); }

// One link by the conventions.h formula, with 4x4 matrices.
M4 RefLink(const AxisLink& l, const LinkErrors& e, double q) {
  const int dir = static_cast<int>(l.axis) % 3;
  const double s = l.branch == Branch::kTool ? 1.0 : -1.0;
  const M4 P = Tr(l.pivot_mm), Pinv = Tr(-l.pivot_mm);
  const M4 Et = Tr(e[0], e[1], e[2]);
  const M4 Er = D4(e[3]) * D5(e[4]) * D6(e[5]);
  const M4 Lr = D4(e[9]) * D5(e[10]) * D6(e[11]);
  if (static_cast<int>(l.axis) >= 3) {
    const M4 Lt = Tr(e[6], e[7], e[8]);
    const M4 G = Lt * Lr * RotAbout(dir, s * q) * Lr.inverse() * Lt.inverse();
    return P * Et * Er * G * Pinv;
  }
  Eigen::Vector4d a = Eigen::Vector4d::Zero();
  a(dir) = 1.0;
  const Eigen::Vector4d d = Lr * a;  // direction of travel (w = 0: rotation only)
  return P * Tr(s * q * d.x(), s * q * d.y(), s * q * d.z()) * Et * Er * Pinv;
}

M4 RefPartFromTool(const MachineModel& m, const std::vector<LinkErrors>& e, const AxisState& s) {
  M4 w = M4::Identity(), t = M4::Identity();
  const double q[6] = {s.x_mm, s.y_mm, s.z_mm, s.a_rad, s.b_rad, s.c_rad};
  for (int i = 0; i < m.num_links(); ++i) {
    const M4 L = RefLink(m.links[i], e[i], q[static_cast<int>(m.links[i].axis)]);
    if (i < m.num_workpiece_links) {
      w = w * L;
    } else {
      t = t * L;
    }
  }
  return w.inverse() * t;
}

MachineModel RandomPivots(MachineModel m, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-300.0, 300.0);
  for (AxisLink& l : m.links) l.pivot_mm = Eigen::Vector3d{u(rng), u(rng), u(rng)};
  return m;
}

std::vector<LinkErrors> RandomErrors(const MachineModel& m, double scale, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<LinkErrors> e(m.num_links());
  for (int i = 0; i < m.num_links(); ++i) {
    for (int c = 0; c < kNumComponents; ++c) {
      const bool line_t = c >= 6 && c <= 8;
      e[i][c] = (line_t && !IsRotary(m.links[i].axis)) ? 0.0 : scale * u(rng) * (IsAngular(static_cast<Component>(c)) ? 0.2 : 2.0);
    }
  }
  return e;
}

AxisState RandomAxes(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> lin(-500.0, 500.0), rot(-3.2, 3.2);
  AxisState s;
  s.x_mm = lin(rng); s.y_mm = lin(rng); s.z_mm = lin(rng);
  s.a_rad = rot(rng); s.b_rad = rot(rng); s.c_rad = rot(rng);
  return s;
}

TEST(ChainReference, AllMachineTypesMatchIndependent4x4Composition) {
  // Truth: the 4x4 products above. Tolerance: double rounding through ~20 matrix products with
  // translations up to ~1000 mm: 1e-9 mm and 1e-12 in the rotation.
  std::mt19937_64 rng(20240611);
  const std::vector<std::pair<MachineType, MachineLayout>> machines = {
      {MachineType::kAcTable, {}},
      {MachineType::kBcTable, {}},
      {MachineType::kBheadCtable, {}},
      {MachineType::kXyz, {}},
      {MachineType::kXyz, {{Axis::kY, Axis::kX}, {Axis::kZ}}},             // moving table X/Y
      {MachineType::kAcTable, {{Axis::kY, Axis::kA, Axis::kC}, {Axis::kX, Axis::kZ}}},
  };
  for (const auto& [type, layout] : machines) {
    Result<MachineModel> base = MakeMachine(type, layout);
    ASSERT_TRUE(base.ok()) << base.status().ToString();
    for (int trial = 0; trial < 50; ++trial) {
      const MachineModel m = RandomPivots(*base, rng);
      const std::vector<LinkErrors> e = RandomErrors(m, trial == 0 ? 0.0 : 1.0, rng);
      const AxisState s = RandomAxes(rng);
      const Rigid3 lib = PartFromToolWithLinkErrors(m, e, s);
      const M4 ref = RefPartFromTool(m, e, s);
      const M4 diff = lib.matrix() - ref;
      const double dt = diff.block(0, 3, 3, 1).cwiseAbs().maxCoeff();
      const double dr = diff.block(0, 0, 3, 3).cwiseAbs().maxCoeff();
      EXPECT_LT(dt, 1e-9) << MachineTypeName(type) << " trial " << trial;
      EXPECT_LT(dr, 1e-12) << MachineTypeName(type) << " trial " << trial;
    }
  }
}

TEST(ChainReference, NominalTableMatchesIso841Formula) {
  // conventions.h: nominal A/C table, pivots at the origin: part_from_machine = RotZ(C) RotX(A).
  std::mt19937_64 rng(7);
  Result<MachineModel> m = MakeMachine(MachineType::kAcTable);
  ASSERT_TRUE(m.ok());
  for (int i = 0; i < 20; ++i) {
    const AxisState s = RandomAxes(rng);
    const Eigen::Vector3d tool(s.x_mm, s.y_mm, s.z_mm);
    const Eigen::Vector4d expect = D6(s.c_rad) * D4(s.a_rad) * tool.homogeneous();
    EXPECT_LT((NominalToolPointInPart(*m, s, Eigen::Vector3d::Zero()) - expect.head<3>()).norm(), 1e-9);
  }
}

}  // namespace
}  // namespace tpcal::kinematics

namespace tpcal::kinematics {
namespace {

TEST(ChainReference, WorkspaceMemoFollowsModelAndErrorChanges) {
  // The double chain memoises link transforms in the Workspace; reusing one Workspace across
  // machines, pivots, errors and positions must give the same results as a fresh Workspace.
  std::mt19937_64 rng(99);
  Workspace shared;
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const MachineType t = static_cast<MachineType>(trial % 4);
    Result<MachineModel> m = MakeMachine(t);
    ASSERT_TRUE(m.ok());
    if (trial % 3 == 0) m->links[0].pivot_mm.x() += 10.0 * u(rng);
    ErrorState e(*m);
    if (trial % 2 == 0) {
      const std::vector<ParameterInfo> cat = ParameterCatalog(*m);
      for (int k = 0; k < 4 && !cat.empty(); ++k) {
        const ParameterInfo& p = cat[static_cast<size_t>(std::abs(u(rng)) * cat.size()) % cat.size()];
        ASSERT_TRUE(e.SetParameter(*m, p.name, 1e-3 * u(rng)).ok());
      }
    }
    AxisState s;
    s.x_mm = 100 * u(rng);
    s.c_rad = trial % 5 == 0 ? 0.0 : u(rng);
    s.b_rad = trial % 7 == 0 ? 0.0 : u(rng);
    s.a_rad = u(rng);
    Workspace fresh;
    const Rigid3 a = PartFromTool(*m, e, s, &shared);
    const Rigid3 b = PartFromTool(*m, e, s, &fresh);
    EXPECT_EQ((a.matrix() - b.matrix()).cwiseAbs().maxCoeff(), 0.0) << trial;
  }
}

// The nominal chain through a Workspace's memo gives the nominal chain's figures, bit for bit,
// with one Workspace reused across the four machines, moved pivots and positions in which one
// linear axis or the rotaries change (as testpieces' RotaryFrame::At asks for them).
TEST(ChainReference, NominalChainThroughTheMemoIsTheSameBits) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Workspace shared;
  for (int trial = 0; trial < 200; ++trial) {
    Result<MachineModel> m = MakeMachine(static_cast<MachineType>(trial % 4));
    ASSERT_TRUE(m.ok());
    if (trial % 3 == 0) m->links.back().pivot_mm.y() += 50.0 * u(rng);
    AxisState s;
    s.a_rad = trial % 5 == 0 ? 0.0 : u(rng);
    s.b_rad = u(rng);
    s.c_rad = 3.0 * u(rng);
    for (int i = 0; i < 4; ++i) {
      AxisState si = s;
      if (i > 0) SetPosition(&si, AxisFromIndex(i - 1), 100.0 * u(rng));
      const Rigid3 a = NominalPartFromTool(*m, si, &shared);
      const Rigid3 b = NominalPartFromTool(*m, si);
      EXPECT_EQ((a.matrix() - b.matrix()).cwiseAbs().maxCoeff(), 0.0) << trial << " " << i;
    }
  }
}

}  // namespace
}  // namespace tpcal::kinematics
