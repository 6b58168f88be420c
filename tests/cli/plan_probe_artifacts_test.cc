// `tpcal plan --instrument probe_artifacts` and `tpcal simulate --instrument probe_artifacts`: the
// plan is a tpcal probepts v1 plan that pipeline::ReadProbePoints reads back, with touches at all
// 24 poses of seed 000's pattern (A 0, -30, -60, -90 deg x C every 60 deg) and every skipped touch
// named on stderr; --nc writes the LinuxCNC program (one G38.2 per planned touch) and its tool
// table; simulate with the bundled seed 000 error map writes a measurement (not a plan) of the
// same touches; a malformed artifact file exits 2 with file:line and writes nothing.
#include <algorithm>
#include <set>
#include <utility>

#include "pipeline/io/probepts_io.h"
#include "tests/cli/plan_simulate_run.h"

namespace tpcal::cli_test {
namespace {

using ProbeArtifactsCli = CliTest;

std::size_t ProbeCliCount(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

TEST_F(ProbeArtifactsCli, PlanReadsBackWithTouchesAtAll24Poses) {
  const RunResult r = Run("plan --instrument probe_artifacts -o plan.csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto file = pipeline::ReadProbePoints(Path("plan.csv"));
  ASSERT_TRUE(file.ok()) << file.status().ToString();
  EXPECT_TRUE(file->is_plan);
  EXPECT_EQ(file->rotary_axes, (std::vector<char>{'A', 'C'}));
  std::set<std::pair<double, double>> poses;
  for (const pipeline::ProbePointRow& row : file->rows) poses.insert({row.rotary_deg.at('A'), row.rotary_deg.at('C')});
  EXPECT_EQ(poses.size(), 24u);
  EXPECT_TRUE(poses.count({-90.0, 300.0}) == 1 && poses.count({0.0, 0.0}) == 1);
  // Every touch (24 poses x 3 columns x 5 faces) is a row or a line on stderr with its reason.
  const std::size_t skipped = ProbeCliCount(r.err, " skipped: ");
  EXPECT_GT(skipped, 0u) << r.err;
  EXPECT_EQ(file->rows.size() + skipped, 360u) << r.err;
  EXPECT_NE(r.err.find("skipped: faces down"), std::string::npos) << r.err;
}

TEST_F(ProbeArtifactsCli, NcWritesTheLinuxCncProgramAndToolTable) {
  const RunResult r = Run("plan --instrument probe_artifacts -o plan.csv --nc pa.ngc --date none");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto file = pipeline::ReadProbePoints(Path("plan.csv"));
  ASSERT_TRUE(file.ok()) << file.status().ToString();
  const std::string program = ReadText(Path("pa.ngc"));
  EXPECT_EQ(ProbeCliCount(program, "G38.2"), file->rows.size());
  EXPECT_TRUE(std::filesystem::exists(Path("pa.ngc.tbl")));
  EXPECT_NE(r.err.find("wrote pa.ngc (LinuxCNC"), std::string::npos) << r.err;
}

TEST_F(ProbeArtifactsCli, SimulateWritesAMeasurementOfThePlannedTouches) {
  const std::string errors = Source("samples/errors/seed000_error_map_example.yaml");
  ASSERT_EQ(Run("plan --instrument probe_artifacts -o plan.csv").exit_code, 0);
  const RunResult r = Run("simulate --instrument probe_artifacts --errors " + errors +
                          " --noise-um 0.3 --seed 1 --pretravel-um 1.5 -o probepts.csv --truth truth.yaml");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto plan = pipeline::ReadProbePoints(Path("plan.csv"));
  auto sim = pipeline::ReadProbePoints(Path("probepts.csv"));
  ASSERT_TRUE(plan.ok() && sim.ok()) << sim.status().ToString();
  EXPECT_FALSE(sim->is_plan);
  ASSERT_EQ(sim->rows.size(), plan->rows.size());
  double largest_um = 0.0;
  for (std::size_t i = 0; i < sim->rows.size(); ++i) {
    EXPECT_EQ(sim->rows[i].rotary_deg, plan->rows[i].rotary_deg) << i;
    EXPECT_EQ(sim->rows[i].artifact, plan->rows[i].artifact) << i;
    EXPECT_EQ(sim->rows[i].face, plan->rows[i].face) << i;
    EXPECT_EQ(sim->rows[i].approach, plan->rows[i].approach) << i;
    largest_um = std::max(largest_um, 1e3 * (sim->rows[i].point_mm - plan->rows[i].point_mm).norm());
  }
  // The map's errors (tens of urad over ~150 mm) and 1.5 um pre-travel move the readings by
  // micrometres, far from the plan's mm: between 1 and 50 um at the worst touch.
  EXPECT_GT(largest_um, 1.0);
  EXPECT_LT(largest_um, 50.0);
  const std::string truth = ReadText(Path("truth.yaml"));
  EXPECT_NE(truth.find("instrument: probe_artifacts\n"), std::string::npos) << truth;
  EXPECT_NE(truth.find("seed: 1 "), std::string::npos) << truth;
  EXPECT_NE(truth.find("pretravel_um: 1.5 "), std::string::npos) << truth;
  EXPECT_NE(truth.find("symbol: E_AA"), std::string::npos) << truth;
}

TEST_F(ProbeArtifactsCli, MalformedArtifactFileExitsTwoWithFileLine) {
  WriteText(Path("a.yaml"), "schema: tpcal.artifacts/1\nartifacts:\n  - {name: \"1\", base_centre_mm: [100, 0, 0], "
                            "size_mm: [30, -30, 60]}\n");
  const RunResult plan = Run("plan --instrument probe_artifacts --artifacts a.yaml -o plan.csv --nc pa.ngc");
  EXPECT_EQ(plan.exit_code, 2);
  EXPECT_EQ(plan.err.rfind("a.yaml:3: ", 0), 0u) << plan.err;
  const RunResult sim = Run("simulate --instrument probe_artifacts --artifacts a.yaml --errors " +
                            Source("samples/errors/seed000_error_map_example.yaml") + " -o probepts.csv");
  EXPECT_EQ(sim.exit_code, 2);
  EXPECT_EQ(sim.err.rfind("a.yaml:3: ", 0), 0u) << sim.err;
  for (const char* name : {"plan.csv", "pa.ngc", "pa.ngc.tbl", "probepts.csv"})
    EXPECT_FALSE(std::filesystem::exists(Path(name))) << name;
}

TEST_F(ProbeArtifactsCli, OptionsOfTheOtherModeAreRefused) {
  const RunResult artifacts = Run("plan --testpiece turning --artifacts a.yaml -o plan.csv");
  EXPECT_EQ(artifacts.exit_code, 2);
  EXPECT_NE(artifacts.err.find("--artifacts needs --instrument probe_artifacts"), std::string::npos) << artifacts.err;
  const RunResult ball = Run("plan --instrument probe_artifacts --ball 1,2,3 -o plan.csv");
  EXPECT_EQ(ball.exit_code, 2);
  EXPECT_NE(ball.err.find("--ball is for --instrument datum_ball"), std::string::npos) << ball.err;
  const RunResult pretravel = Run("simulate --instrument datum_ball --errors " +
                                  Source("samples/errors/seed001_table1a.yaml") + " --pretravel-um 1 -o b.csv");
  EXPECT_EQ(pretravel.exit_code, 2);
  EXPECT_NE(pretravel.err.find("--pretravel-um is not an option of --instrument datum_ball"), std::string::npos)
      << pretravel.err;
  EXPECT_FALSE(std::filesystem::exists(Path("plan.csv")));
  EXPECT_FALSE(std::filesystem::exists(Path("b.csv")));
}

}  // namespace
}  // namespace tpcal::cli_test
