// Nominal inverse kinematics: round trips through the forward chain on every machine type,
// tool-axis solutions, stroke failures.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <random>

#include "core/units.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/inverse_kinematics.h"
#include "kinematics/machine_yaml.h"

namespace tpcal::kinematics {
namespace {

TEST(InverseKinematics, ToolPointRoundTripsOnEveryMachine) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const char* f : {"ac_table.yaml", "bc_table.yaml", "bhead_ctable.yaml", "xyz.yaml"}) {
    Result<MachineModel> m = LoadMachineModel(std::string(TPCAL_SOURCE_DIR) + "/samples/machines/" + f);
    ASSERT_TRUE(m.ok());
    InverseKinematicsOptions no_strokes;
    no_strokes.check_strokes = false;
    for (int i = 0; i < 50; ++i) {
      AxisState rot;
      if (m->HasAxis(Axis::kA)) rot.a_rad = DegToRad(-90.0 * std::abs(u(rng)));
      if (m->HasAxis(Axis::kB)) rot.b_rad = DegToRad(60.0 * u(rng));
      if (m->HasAxis(Axis::kC)) rot.c_rad = DegToRad(180.0 * u(rng));
      rot.t_s = 12.5;
      rot.op = 3;
      const Eigen::Vector3d target{150 * u(rng), 150 * u(rng), 100 + 100 * u(rng)};
      const Eigen::Vector3d contact{5 * u(rng), 5 * u(rng), 2 * u(rng)};
      Result<AxisState> s = NominalAxesForToolPoint(*m, target, rot, contact, no_strokes);
      ASSERT_TRUE(s.ok()) << s.status().ToString();
      EXPECT_LT((NominalToolPointInPart(*m, *s, contact) - target).norm(), 1e-9) << f;
      EXPECT_EQ(s->a_rad, rot.a_rad);
      EXPECT_EQ(s->c_rad, rot.c_rad);
      EXPECT_EQ(s->op, 3);
    }
  }
}

TEST(InverseKinematics, TableMachineIsMachineFromPartTimesPoint) {
  // conventions.h: X, Y, Z = machine_from_part(A, C) * p_part = RotX(-A) RotZ(-C) p.
  Result<MachineModel> m = MakeMachine(MachineType::kAcTable);
  ASSERT_TRUE(m.ok());
  AxisState rot;
  rot.a_rad = DegToRad(-90);
  rot.c_rad = DegToRad(30);
  const Eigen::Vector3d p(170, 0, 380.702);
  Result<AxisState> s = NominalAxesForToolPoint(*m, p, rot);
  ASSERT_TRUE(s.ok());
  const Eigen::Vector3d expect = Eigen::AngleAxisd(-rot.a_rad, Eigen::Vector3d::UnitX()) *
                                 (Eigen::AngleAxisd(-rot.c_rad, Eigen::Vector3d::UnitZ()) * p);
  EXPECT_LT((Eigen::Vector3d(s->x_mm, s->y_mm, s->z_mm) - expect).norm(), 1e-9);
}

TEST(InverseKinematics, RotaryAnglesForToolAxis) {
  std::mt19937_64 rng(32);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (MachineType t : {MachineType::kAcTable, MachineType::kBcTable, MachineType::kBheadCtable}) {
    Result<MachineModel> m = MakeMachine(t);
    ASSERT_TRUE(m.ok());
    for (int i = 0; i < 50; ++i) {
      const Eigen::Vector3d d = Eigen::Vector3d{u(rng), u(rng), u(rng)}.normalized();
      Result<std::vector<AxisState>> sols = RotaryAnglesForToolAxis(*m, d);
      ASSERT_TRUE(sols.ok()) << sols.status().ToString();
      EXPECT_EQ(sols->size(), 2u);
      for (const AxisState& s : *sols) EXPECT_LT((NominalToolAxisInPart(*m, s) - d).norm(), 1e-9);
    }
    Result<std::vector<AxisState>> up = RotaryAnglesForToolAxis(*m, Eigen::Vector3d::UnitZ(), 0.7);
    ASSERT_TRUE(up.ok());
    ASSERT_EQ(up->size(), 1u);
    EXPECT_DOUBLE_EQ(up->front().c_rad, 0.7);
  }
  Result<MachineModel> xyz = MakeMachine(MachineType::kXyz);
  EXPECT_FALSE(RotaryAnglesForToolAxis(*xyz, Eigen::Vector3d::UnitX()).ok());
}

TEST(InverseKinematics, StrokesAreChecked) {
  Result<MachineModel> m = LoadMachineModel(std::string(TPCAL_SOURCE_DIR) + "/samples/machines/ac_table.yaml");
  ASSERT_TRUE(m.ok());
  Result<AxisState> far = NominalAxesForToolPoint(*m, Eigen::Vector3d(2000, 0, 0), AxisState{});
  ASSERT_FALSE(far.ok());
  EXPECT_THAT(far.status().message(), ::testing::HasSubstr("axis X"));
  // Tool axis along part -Y: A = +90, C = 0 or A = -90, C = 180 deg; the A stroke [-120, 30] deg
  // keeps only the second.
  Result<std::vector<AxisState>> sols = RotaryAnglesForToolAxis(*m, Eigen::Vector3d(0, -1, 0));
  ASSERT_TRUE(sols.ok());
  ASSERT_EQ(sols->size(), 1u);
  EXPECT_NEAR(sols->front().a_rad, DegToRad(-90), 1e-12);
  EXPECT_NEAR(std::abs(sols->front().c_rad), DegToRad(180), 1e-12);
}

}  // namespace
}  // namespace tpcal::kinematics
