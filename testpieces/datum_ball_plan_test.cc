// The datum-ball plan: seed 001's pattern by default (tilt 0, +-30 deg, C every 30 deg: 36
// positions, exact angles), A in place of B on the A/C table, and bad options named.
#include "testpieces/datum_ball_plan.h"

#include <gtest/gtest.h>

#include "core/units.h"

namespace tpcal::testpieces {
namespace {

TEST(DatumBallPlan, DefaultIsSeed001sThreeTiltsWithCEveryThirtyDegrees) {
  auto m = kinematics::MakeMachine(kinematics::MachineType::kBcTable);
  ASSERT_TRUE(m.ok());
  auto plan = MakeDatumBallPlan(*m);
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  EXPECT_EQ(plan->tilt_axis, kinematics::Axis::kB);
  ASSERT_EQ(plan->positions.size(), 36u);
  EXPECT_EQ(plan->positions[13].b_rad, DegToRad(30.0));
  EXPECT_EQ(plan->positions[13].c_rad, DegToRad(30.0));
  EXPECT_EQ(plan->positions[35].b_rad, DegToRad(-30.0));
  EXPECT_EQ(plan->positions[35].c_rad, DegToRad(330.0));
  EXPECT_EQ(plan->positions[35].a_rad, 0.0);
  EXPECT_EQ(plan->ball_part_mm, Eigen::Vector3d(200.0, 0.1, 300.0));
}

TEST(DatumBallPlan, AcTableTiltsAAndBadOptionsAreNamed) {
  auto ac = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  ASSERT_TRUE(ac.ok());
  auto plan = MakeDatumBallPlan(*ac, {.tilt_deg = {0.0, -90.0}, .c_step_deg = 60.0});
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  EXPECT_EQ(plan->tilt_axis, kinematics::Axis::kA);
  ASSERT_EQ(plan->positions.size(), 12u);
  EXPECT_EQ(plan->positions[7].a_rad, DegToRad(-90.0));
  EXPECT_EQ(plan->positions[7].b_rad, 0.0);

  EXPECT_FALSE(MakeDatumBallPlan(*ac, {.tilt_deg = {}}).ok());
  EXPECT_FALSE(MakeDatumBallPlan(*ac, {.c_step_deg = 0.0}).ok());
  EXPECT_FALSE(MakeDatumBallPlan(*ac, {.ball_diameter_mm = 0.0}).ok());
  auto xyz = kinematics::MakeMachine(kinematics::MachineType::kXyz);
  ASSERT_TRUE(xyz.ok());
  auto bad = MakeDatumBallPlan(*xyz);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("expected bc_table or ac_table"), std::string::npos);
}

}  // namespace
}  // namespace tpcal::testpieces
