// The virtual double ball bar (pipeline/ballbar_simulate_stage.h) with seed 003's installations on
// the nominal B-head / C-table machine. What each reading must be is
// kinematics::SimulateBallbarDlUm under the same errors (tested on its own in
// kinematics/ballbar_test.cc); this test pins the stage's bookkeeping: plan order, the noise
// draws, the 0.1 um rounding, times, the truth, located errors.
#include "pipeline/ballbar_simulate_stage.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "core/portable_random.h"
#include "kinematics/ballbar.h"
#include "kinematics/errors_yaml.h"

namespace tpcal::pipeline {
namespace {

const char kBarSimErrorsYaml[] = "schema: tpcal.errors/1\nE_X0C_um: 10\nE_Y0C_um: -4\nE_B0C_urad: 20\n";

struct BarSimCase {
  kinematics::MachineModel machine;
  kinematics::ErrorState errors;
  kinematics::BallbarSetup setup;
};

BarSimCase BarSimSeed003(const std::string& yaml = kBarSimErrorsYaml) {
  auto m = kinematics::MakeMachine(kinematics::MachineType::kBheadCtable);
  EXPECT_TRUE(m.ok());
  auto e = kinematics::ParseErrorState(yaml, "errors.yaml", *m);
  EXPECT_TRUE(e.ok()) << e.status().ToString();
  auto s = kinematics::LoadBallbarSetup(std::string(TPCAL_SOURCE_DIR) + "/samples/ballbar/seed003_setups.yaml");
  EXPECT_TRUE(s.ok()) << s.status().ToString();
  return {*m, *e, *s};
}

TEST(BallbarSimulateStage, ReadingsAreTheModelsPlusNoiseInPlanOrder) {
  const BarSimCase c = BarSimSeed003();
  BallbarSimRequest r;
  r.noise_um = 0.5;
  r.seed = 7;
  r.truth = true;
  auto sim = SimulateBallbar(c.machine, c.errors, c.setup, r);
  ASSERT_TRUE(sim.ok()) << sim.status().ToString();
  EXPECT_FALSE(sim->timed);
  ASSERT_EQ(sim->file.rows.size(), 7u * 19u + 6u * 21u);
  std::mt19937_64 rng(7);
  kinematics::Workspace ws;
  double largest_um = 0.0;
  for (std::size_t i = 0; i < sim->file.rows.size(); ++i) {
    const BallbarRow& row = sim->file.rows[i];
    auto g = kinematics::MakeBallbarGeometry(c.machine, *c.setup.Find(row.setup));
    ASSERT_TRUE(g.ok());
    auto dl = kinematics::SimulateBallbarDlUm(c.machine, c.errors, *g, row.angle_deg, 0.0, &ws);
    ASSERT_TRUE(dl.ok());
    const double expected = *dl + 0.5 * StandardNormal(rng);
    EXPECT_NEAR(sim->dl_um[i], expected, 1e-9) << i;
    EXPECT_NEAR(row.dl_um, expected, 0.05 + 1e-9) << i;
    largest_um = std::max(largest_um, std::abs(*dl));
  }
  EXPECT_GT(largest_um, 1.0);  // the errors show (10 um of C position on a radial bar)
  auto back = ParseBallbar(sim->csv, "ballbar.csv");
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ(back->rows.size(), sim->file.rows.size());
  EXPECT_NE(sim->truth_yaml.find("instrument: ballbar\n"), std::string::npos);
  EXPECT_NE(sim->truth_yaml.find("seed: 7 "), std::string::npos);
  EXPECT_NE(sim->truth_yaml.find("  \"C_radial_L1H1\": [0, 20, 40"), std::string::npos) << sim->truth_yaml;
  EXPECT_NE(sim->truth_yaml.find("E_X0C"), std::string::npos);
}

TEST(BallbarSimulateStage, ThermalTermsGiveTimedReadings) {
  const BarSimCase c = BarSimSeed003(
      "schema: tpcal.errors/1\neffects:\n  - thermal_drift: {parameter: E_X0C, K_um: 8, tau_s: 1200}\n");
  BallbarSimRequest r;
  r.seconds_per_reading = 2.0;
  auto sim = SimulateBallbar(c.machine, c.errors, c.setup, r);
  ASSERT_TRUE(sim.ok()) << sim.status().ToString();
  EXPECT_TRUE(sim->timed);
  EXPECT_EQ(sim->file.rows[10].t_s, 20.0);
  EXPECT_NE(sim->csv.find(",t_s\n"), std::string::npos);
}

TEST(BallbarSimulateStage, BadInputIsLocated) {
  BallbarSimRequest r;
  r.errors_path = "e.yaml";
  EXPECT_EQ(RunBallbarSimulateStage(r).status().message(), "--setup S.yaml is needed with --instrument ballbar");
  r.setup_path = std::string(TPCAL_SOURCE_DIR) + "/samples/ballbar/seed003_setups.yaml";
  r.noise_um = -1.0;
  EXPECT_NE(RunBallbarSimulateStage(r).status().message().find("--noise-um"), std::string::npos);
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "tpcal_bar_sim_stage";
  std::filesystem::create_directories(dir);
  const std::string setup = (dir / "bad.yaml").string();
  std::ofstream(setup) << "schema: tpcal.ballbar_setup/1\ninstallations:\n  - {name: X, kind: spiral, axis: C}\n";
  r.noise_um = 0.0;
  r.setup_path = setup;
  auto bad = RunBallbarSimulateStage(r);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().file(), setup) << bad.status().ToString();
  EXPECT_EQ(bad.status().line(), 3u) << bad.status().ToString();
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace tpcal::pipeline
