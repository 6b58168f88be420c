// The ball-bar plan stage (pipeline/ballbar_plan_stage.h) with seed 003's installations
// (samples/ballbar/seed003_setups.yaml) on the nominal B-head / C-table machine. Truth: the plan
// is the readings to take, dl_um 0, at seed 003's angles (Tables 1 and 2: C 0..360 every 20 deg,
// B 0..-100 every 5 deg); circles are read at every degree ccw then cw.
#include "pipeline/ballbar_plan_stage.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/units.h"

namespace tpcal::pipeline {
namespace {

std::string BarPlanSample() { return std::string(TPCAL_SOURCE_DIR) + "/samples/ballbar/seed003_setups.yaml"; }

BallbarPlanRequest BarPlanRequest() {
  BallbarPlanRequest r;
  r.setup_path = BarPlanSample();
  r.csv_path = "plan.csv";
  return r;
}

TEST(BallbarPlanStage, Seed003PlanReadsBackWithTheTablesAngles) {
  auto r = RunBallbarPlanStage(BarPlanRequest());
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->machine, "bhead_ctable");
  ASSERT_EQ(r->files.size(), 1u);
  EXPECT_NE(r->csv.find("\n# plan: nominal readings of an error-free bhead_ctable"), std::string::npos);
  auto file = ParseBallbar(r->csv, "plan.csv");
  ASSERT_TRUE(file.ok()) << file.status().ToString();
  EXPECT_FALSE(file->has_direction);
  // 7 C installations x 19 angles, 6 B installations x 21 angles.
  ASSERT_EQ(file->rows.size(), 7u * 19u + 6u * 21u);
  for (const BallbarRow& row : file->rows) EXPECT_EQ(row.dl_um, 0.0);
  EXPECT_EQ(file->rows[0].setup, "C_radial_L1H1");
  EXPECT_EQ(file->rows[18].angle_deg, 360.0);
  EXPECT_EQ(file->rows[19].setup, "C_tangential_L1H1");
  EXPECT_EQ(file->rows[7 * 19].setup, "B_radial_L1");
  EXPECT_EQ(file->rows[7 * 19 + 20].angle_deg, -100.0);
}

TEST(BallbarPlanStage, CirclesAreReadCcwThenCwAndTheProgramPosts) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "tpcal_bar_plan_stage";
  std::filesystem::create_directories(dir);
  const std::string setup = (dir / "circles.yaml").string();
  std::ofstream(setup) << "schema: tpcal.ballbar_setup/1\ninstallations:\n"
                          "  - {name: XY, kind: circle, axis: XY, workpiece_ball_in_part_mm: [0, 0, 200], "
                          "tool_ball_in_tool_mm: [0, 0, 0], nominal_length_mm: 100}\n"
                          "  - {name: C_axial, kind: axial, axis: C, workpiece_ball_in_part_mm: [0, 0, 50], "
                          "tool_ball_in_tool_mm: [0, 0, 0], nominal_length_mm: 150}\n";
  BallbarPlanRequest r;
  r.setup_path = setup;
  r.csv_path = (dir / "plan.csv").string();
  r.angles.step_deg = 90.0;
  r.nc.output = (dir / "bar.ngc").string();
  r.nc.date = "none";
  auto p = RunBallbarPlanStage(r);
  ASSERT_TRUE(p.ok()) << p.status().ToString();
  ASSERT_EQ(p->files.size(), 3u);  // plan, program, tool table
  auto file = ParseBallbar(p->csv, "plan.csv");
  ASSERT_TRUE(file.ok()) << file.status().ToString();
  ASSERT_TRUE(file->has_direction);
  ASSERT_EQ(file->rows.size(), 8u + 5u);
  const std::vector<double> expected = {0, 90, 180, 270, 270, 180, 90, 0, 0, 90, 180, 270, 360};
  for (std::size_t i = 0; i < file->rows.size(); ++i) {
    EXPECT_EQ(file->rows[i].angle_deg, expected[i]) << i;
    EXPECT_EQ(file->rows[i].direction, i >= 4 && i < 8 ? BallbarDirection::kCw : BallbarDirection::kCcw) << i;
  }
  EXPECT_NE(p->posted->program_text.find("G3 X"), std::string::npos);
  EXPECT_NE(p->posted->program_text.find("MOUNT THE BALL BAR: C_axial"), std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST(BallbarPlanStage, BadInputIsLocated) {
  BallbarPlanRequest r = BarPlanRequest();
  r.setup_path.clear();
  EXPECT_EQ(RunBallbarPlanStage(r).status().message(), "--setup S.yaml is needed with --instrument ballbar");
  r = BarPlanRequest();
  r.angles.step_deg = 0.0;
  auto step = RunBallbarPlanStage(r);
  ASSERT_FALSE(step.ok());
  EXPECT_EQ(step.status().file(), "tpcal plan");
  EXPECT_NE(step.status().message().find("--step-deg: expected a step in (0, 360] deg"), std::string::npos);
  r = BarPlanRequest();
  r.angles.angles_deg = {0.0, 10.0, 0.0};
  EXPECT_NE(RunBallbarPlanStage(r).status().message().find("--angles-deg: 0 deg is given twice"), std::string::npos);
  r = BarPlanRequest();
  r.machine_path = std::string(TPCAL_SOURCE_DIR) + "/samples/machines/ac_table.yaml";  // no B axis
  auto machine = RunBallbarPlanStage(r);
  ASSERT_FALSE(machine.ok());
  EXPECT_EQ(machine.status().file(), BarPlanSample()) << machine.status().ToString();
  r = BarPlanRequest();
  r.program.feed_mm_per_min = 0.0;
  EXPECT_EQ(RunBallbarPlanStage(r).status().message(), "--feed-mm-per-min: expected a feed > 0 mm/min, got 0");
  r = BarPlanRequest();
  r.nc.dialect = "fanuc";
  EXPECT_EQ(RunBallbarPlanStage(r).status().message(), "--dialect needs --nc PROGRAM");
  r = BarPlanRequest();
  r.nc.output = "bar.txt";
  EXPECT_NE(RunBallbarPlanStage(r).status().message().find("--dialect: needed for --nc bar.txt"), std::string::npos);
}

}  // namespace
}  // namespace tpcal::pipeline
