// `tpcal plan --instrument ballbar` and `tpcal simulate --instrument ballbar`: the plan of seed
// 003's installations is a tpcal ballbar v1 file that pipeline::ReadBallbar reads back (dl_um 0,
// Tables 1 and 2's angles); --nc writes the LinuxCNC program (an M0 to mount and one to remove the
// bar per installation) and its tool table; simulate with seed 003's mean errors writes the same
// readings with bar-length changes of micrometres and the truth; bad input exits 2 with file:line
// and writes nothing.
#include <cmath>

#include "pipeline/io/ballbar_io.h"
#include "tests/cli/plan_simulate_run.h"

namespace tpcal::cli_test {
namespace {

using BallbarCli = CliTest;

std::size_t BarCliCount(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

TEST_F(BallbarCli, PlanAndProgramOfSeed003) {
  const RunResult r = Run("plan --instrument ballbar --setup " + Source("samples/ballbar/seed003_setups.yaml") +
                          " -o plan.csv --nc bb.ngc --date none --feed-mm-per-min 2000");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto file = pipeline::ReadBallbar(Path("plan.csv"));
  ASSERT_TRUE(file.ok()) << file.status().ToString();
  EXPECT_EQ(file->rows.size(), 7u * 19u + 6u * 21u);
  for (const pipeline::BallbarRow& row : file->rows) EXPECT_EQ(row.dl_um, 0.0);
  const std::string program = ReadText(Path("bb.ngc"));
  EXPECT_EQ(BarCliCount(program, "M0\n"), 26u);
  EXPECT_TRUE(std::filesystem::exists(Path("bb.ngc.tbl")));
  EXPECT_NE(r.err.find("wrote bb.ngc (LinuxCNC"), std::string::npos) << r.err;
}

TEST_F(BallbarCli, SimulateWritesTheReadingsOfThePlan) {
  const std::string setup = Source("samples/ballbar/seed003_setups.yaml");
  ASSERT_EQ(Run("plan --instrument ballbar --setup " + setup + " -o plan.csv").exit_code, 0);
  const RunResult r = Run("simulate --instrument ballbar --setup " + setup + " --errors " +
                          Source("samples/errors/seed003_bhead_ctable_means.yaml") +
                          " --noise-um 0.2 --seed 3 -o ballbar.csv --truth truth.yaml");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto plan = pipeline::ReadBallbar(Path("plan.csv"));
  auto sim = pipeline::ReadBallbar(Path("ballbar.csv"));
  ASSERT_TRUE(plan.ok() && sim.ok()) << sim.status().ToString();
  ASSERT_EQ(sim->rows.size(), plan->rows.size());
  double largest_um = 0.0;
  for (std::size_t i = 0; i < sim->rows.size(); ++i) {
    EXPECT_EQ(sim->rows[i].setup, plan->rows[i].setup) << i;
    EXPECT_EQ(sim->rows[i].angle_deg, plan->rows[i].angle_deg) << i;
    largest_um = std::max(largest_um, std::abs(sim->rows[i].dl_um));
  }
  // Seed 003's mean errors (tens of um and urad) move the bar by micrometres, not millimetres.
  EXPECT_GT(largest_um, 1.0);
  EXPECT_LT(largest_um, 200.0);
  const std::string truth = ReadText(Path("truth.yaml"));
  EXPECT_NE(truth.find("instrument: ballbar\n"), std::string::npos) << truth;
  EXPECT_NE(truth.find("seed: 3 "), std::string::npos) << truth;
}

TEST_F(BallbarCli, BadInputExitsTwoWithFileLineAndWritesNothing) {
  WriteText(Path("s.yaml"), "schema: tpcal.ballbar_setup/1\ninstallations:\n  - {name: X, kind: spiral, axis: C}\n");
  const RunResult plan = Run("plan --instrument ballbar --setup s.yaml -o plan.csv --nc bb.ngc");
  EXPECT_EQ(plan.exit_code, 2);
  EXPECT_EQ(plan.err.rfind("s.yaml:3: ", 0), 0u) << plan.err;
  const RunResult sim = Run("simulate --instrument ballbar --setup s.yaml --errors " +
                            Source("samples/errors/seed003_bhead_ctable_means.yaml") + " -o ballbar.csv");
  EXPECT_EQ(sim.exit_code, 2);
  EXPECT_EQ(sim.err.rfind("s.yaml:3: ", 0), 0u) << sim.err;
  const RunResult no_setup = Run("plan --instrument ballbar -o plan.csv");
  EXPECT_EQ(no_setup.exit_code, 2);
  EXPECT_NE(no_setup.err.find("--setup S.yaml is needed with --instrument ballbar"), std::string::npos) << no_setup.err;
  const RunResult tilt = Run("simulate --instrument ballbar --setup s.yaml --errors e.yaml --tilt-deg 0 -o b.csv");
  EXPECT_EQ(tilt.exit_code, 2);
  EXPECT_NE(tilt.err.find("--tilt-deg is not an option of --instrument ballbar"), std::string::npos) << tilt.err;
  const RunResult setup_elsewhere = Run("plan --instrument datum_ball --setup s.yaml -o plan.csv");
  EXPECT_EQ(setup_elsewhere.exit_code, 2);
  EXPECT_NE(setup_elsewhere.err.find("--setup is for --instrument ballbar, not datum_ball"), std::string::npos)
      << setup_elsewhere.err;
  for (const char* name : {"plan.csv", "bb.ngc", "bb.ngc.tbl", "ballbar.csv", "b.csv"})
    EXPECT_FALSE(std::filesystem::exists(Path(name))) << name;
}

}  // namespace
}  // namespace tpcal::cli_test
