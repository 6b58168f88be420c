// The datum-ball plan stage (pipeline/datum_ball_plan_stage.h). Truth: the nominal centring
// commands (kinematics::BallCentreCommand with zero errors) of seed 001's plan on the nominal B/C
// table. The plan file carries 4 decimals, so a value read back is within 0.05 um (5e-5 mm) of the
// command; identified from the plan, every error is zero within 4 u (u from that rounding, as in
// datum_ball_stage_test.cc) plus 1e-3 um / urad for the printed digits.
#include "pipeline/datum_ball_plan_stage.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/units.h"
#include "kinematics/datum_ball.h"
#include "kinematics/error_state.h"
#include "pipeline/io/ballpos_reader.h"

namespace tpcal::pipeline {
namespace {

constexpr double kPlanRounding_mm = 5e-5;

DatumBallPlanRequest BallPlanRequest() {
  DatumBallPlanRequest r;
  r.csv_path = "plan.csv";
  return r;
}

TEST(DatumBallPlanStage, PlanFileReadsBackAsTheNominalCentringCommands) {
  auto r = RunDatumBallPlanStage(BallPlanRequest());
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->machine, "bc_table");
  ASSERT_EQ(r->files.size(), 1u);
  auto file = ParseBallPositions(r->csv, "plan.csv");
  ASSERT_TRUE(file.ok()) << file.status().ToString();
  ASSERT_EQ(file->rotary_axes, (std::vector<char>{'B', 'C'}));
  ASSERT_EQ(file->rows.size(), 36u);
  EXPECT_NE(r->csv.find("\n# plan: nominal centring commands"), std::string::npos);
  auto m = kinematics::MakeMachine(kinematics::MachineType::kBcTable);
  ASSERT_TRUE(m.ok());
  const kinematics::ErrorState zero(*m);
  for (std::size_t i = 0; i < file->rows.size(); ++i) {
    const BallPositionRow& row = file->rows[i];
    kinematics::AxisState s;
    s.b_rad = DegToRad(row.rotary_deg.at('B')), s.c_rad = DegToRad(row.rotary_deg.at('C'));
    EXPECT_NEAR(row.rotary_deg.at('B'), (i < 12 ? 0.0 : i < 24 ? 30.0 : -30.0), 1e-12);
    EXPECT_NEAR(row.rotary_deg.at('C'), 30.0 * static_cast<double>(i % 12), 1e-12);
    auto c = kinematics::BallCentreCommand(*m, zero, s, Eigen::Vector3d(200.0, 0.1, 300.0));
    ASSERT_TRUE(c.ok());
    EXPECT_LE((row.centre_mm - *c).cwiseAbs().maxCoeff(), kPlanRounding_mm) << "row " << i;
  }
}

TEST(DatumBallPlanStage, PlanIdentifiesAnErrorFreeMachine) {
  auto r = RunDatumBallPlanStage(BallPlanRequest());
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  auto file = ParseBallPositions(r->csv, "plan.csv");
  ASSERT_TRUE(file.ok());
  std::vector<kinematics::BallReading> readings;
  for (const BallPositionRow& row : file->rows) {
    kinematics::BallReading reading;
    reading.rotary.b_rad = DegToRad(row.rotary_deg.at('B'));
    reading.rotary.c_rad = DegToRad(row.rotary_deg.at('C'));
    reading.command_mm = row.centre_mm;
    readings.push_back(reading);
  }
  auto m = kinematics::MakeMachine(kinematics::MachineType::kBcTable);
  ASSERT_TRUE(m.ok());
  auto id = kinematics::IdentifyDatumBall(*m, readings);
  ASSERT_TRUE(id.ok()) << id.status().ToString();
  ASSERT_EQ(id->parameters.size(), 11u);
  for (const auto& p : id->parameters) {
    EXPECT_TRUE(p.identifiable) << p.name;
    EXPECT_LT(std::abs(p.value), 4.0 * p.u + 1e-3) << p.name << " " << p.value << " +- " << p.u;
  }
}

TEST(DatumBallPlanStage, ProgramDialectFromTheExtensionAndItsFiles) {
  DatumBallPlanRequest r = BallPlanRequest();
  r.nc.output = "DB.ngc";
  r.nc.date = "none";
  auto linuxcnc = RunDatumBallPlanStage(r);
  ASSERT_TRUE(linuxcnc.ok()) << linuxcnc.status().ToString();
  ASSERT_EQ(linuxcnc->files.size(), 3u);
  EXPECT_EQ(linuxcnc->files[1].path, "DB.ngc");
  EXPECT_EQ(linuxcnc->files[2].path, "DB.ngc.tbl");
  EXPECT_NE(linuxcnc->files[1].text.find("G38.2"), std::string::npos);
  r.nc.output = "DB.mpf";
  auto sinumerik = RunDatumBallPlanStage(r);
  ASSERT_TRUE(sinumerik.ok()) << sinumerik.status().ToString();
  ASSERT_EQ(sinumerik->files.size(), 2u);
  EXPECT_NE(sinumerik->files[1].text.find("MEAS=1 G1"), std::string::npos);
  EXPECT_NE(sinumerik->files[1].text.find("%_N_DB_MPF"), std::string::npos);
}

TEST(DatumBallPlanStage, AcTableGetsAnAColumn) {
  DatumBallPlanRequest r = BallPlanRequest();
  r.machine_path = std::string(TPCAL_SOURCE_DIR) + "/samples/machines/ac_table.yaml";
  r.tilt_deg = {0.0, -30.0};
  r.c_step_deg = 90.0;
  auto plan = RunDatumBallPlanStage(r);
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  auto file = ParseBallPositions(plan->csv, "plan.csv");
  ASSERT_TRUE(file.ok());
  EXPECT_EQ(file->rotary_axes, (std::vector<char>{'A', 'C'}));
  EXPECT_EQ(file->rows.size(), 8u);
}

TEST(DatumBallPlanStage, BadOptionsNameTheOption) {
  DatumBallPlanRequest r = BallPlanRequest();
  r.ball_part_mm = {200.0, 0.1};
  auto ball = RunDatumBallPlanStage(r);
  ASSERT_FALSE(ball.ok());
  EXPECT_NE(ball.status().ToString().find("--ball: expected x,y,z"), std::string::npos) << ball.status().ToString();
  r = BallPlanRequest();
  r.c_step_deg = 0.0;
  auto step = RunDatumBallPlanStage(r);
  ASSERT_FALSE(step.ok());
  EXPECT_NE(step.status().ToString().find("--c-step-deg"), std::string::npos) << step.status().ToString();
  r = BallPlanRequest();
  r.nc.output = "DB.txt";
  auto dialect = RunDatumBallPlanStage(r);
  ASSERT_FALSE(dialect.ok());
  EXPECT_NE(dialect.status().ToString().find("--dialect"), std::string::npos) << dialect.status().ToString();
  r.nc.dialect = "okuma";
  auto okuma = RunDatumBallPlanStage(r);
  ASSERT_FALSE(okuma.ok());
  EXPECT_NE(okuma.status().ToString().find("--dialect: expected fanuc"), std::string::npos) << okuma.status().ToString();
}

}  // namespace
}  // namespace tpcal::pipeline
