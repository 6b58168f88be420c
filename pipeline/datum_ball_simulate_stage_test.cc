// The virtual datum-ball instrument (pipeline/datum_ball_simulate_stage.h). Truth: seed 001 Table
// 1(a)'s errors on the nominal B/C table (kTable1aYaml, the 11 of samples/errors/seed001_table1a.yaml),
// seed 001's default plan (B = 0, +-30 deg, C every 30 deg: 36 readings, ball (200, 0.1, 300) mm).
// (The sample samples/datum_ball/table1a_ballpos.csv is this instrument's noise-free output:
// pipeline/datum_ball_stage_test.cc.)
#include "pipeline/datum_ball_simulate_stage.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "core/portable_random.h"
#include "core/units.h"
#include "kinematics/errors_yaml.h"

namespace tpcal::pipeline {
namespace {

const char kTable1aYaml[] =
    "E_A(0Y)Z_urad: -34\nE_B(0X)Z_urad: 29\nE_C(0X)Y_urad: 17\nE_A0B_urad: -17\nE_C0B_urad: 75\n"
    "E_X0B_um: -12\nE_Z0B_um: 19\nE_A0C_urad: -87\nE_B0C_urad: 42\nE_X0C_um: 10\nE_Y0C_um: -15\n";

struct BallCase {
  kinematics::MachineModel machine;
  kinematics::ErrorState truth;
};

BallCase Table1a(const std::string& extra_yaml = "") {
  auto m = kinematics::MakeMachine(kinematics::MachineType::kBcTable);
  EXPECT_TRUE(m.ok());
  auto e = kinematics::ParseErrorState(std::string(kTable1aYaml) + extra_yaml, "<test>", *m);
  EXPECT_TRUE(e.ok()) << e.status().ToString();
  return {*m, *e};
}

double DisplayValue(const kinematics::MachineModel& m, const kinematics::ErrorState& e, const std::string& name) {
  auto v = e.Parameter(m, name);
  EXPECT_TRUE(v.ok()) << name;
  auto info = kinematics::LookupParameter(m, name);
  return info->quantity == kinematics::Quantity::kAngle ? *v * 1e6 : MmToUm(*v);
}

// Noise: each coordinate of reading i is the noise-free command plus noise_um times the next
// StandardNormal of std::mt19937_64(seed), x, y, z, reading by reading (what the truth file says).
TEST(DatumBallSimulate, NoiseIsTheStatedDrawsOnTheNoiseFreeCommands) {
  const BallCase c = Table1a();
  DatumBallSimRequest clean;
  DatumBallSimRequest noisy;
  noisy.noise_um = 0.7, noisy.seed = 5, noisy.truth = true;
  auto a = SimulateDatumBall(c.machine, c.truth, clean);
  auto b = SimulateDatumBall(c.machine, c.truth, noisy);
  ASSERT_TRUE(a.ok() && b.ok());
  ASSERT_EQ(a->readings.size(), 36u);
  ASSERT_EQ(b->readings.size(), 36u);
  std::mt19937_64 rng(5);
  for (std::size_t i = 0; i < 36; ++i) {
    auto cmd = kinematics::BallCentreCommand(c.machine, c.truth, a->readings[i].rotary, Eigen::Vector3d(200, 0.1, 300));
    ASSERT_TRUE(cmd.ok());
    EXPECT_EQ(a->readings[i].command_mm, *cmd);
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(b->readings[i].command_mm(k), (*cmd)(k) + UmToMm(0.7 * StandardNormal(rng))) << i << " " << k;
  }
  EXPECT_FALSE(a->timed);
  EXPECT_TRUE(a->truth_yaml.empty());
  EXPECT_NE(b->truth_yaml.find("instrument: datum_ball\n"), std::string::npos);
  EXPECT_NE(b->truth_yaml.find("seed: 5 "), std::string::npos);
  EXPECT_NE(b->truth_yaml.find("noise_um: 0.69999999999999996 "), std::string::npos) << b->truth_yaml;
  EXPECT_NE(b->truth_yaml.find("E_C0B_urad: 75"), std::string::npos) << b->truth_yaml;
}

// Thermal terms: reading i is taken at t_s = 60 i s (the default), centred with the drift at that
// time, and the file says t_s. The drift K (1 - exp(-t / tau)) of E_X0C (a shift of the C table,
// which carries the ball, along X of the B frame) is nil at the first reading (t = 0: the same
// command as without it) and moves the last one (t = 2100 s) by 8 um x (1 - exp(-2100 / 1200)) =
// 6.61 um, up to the shear of the linear axes' squareness errors the command passes through
// (6.6 um x (17 + 29 + 34) urad = 5e-4 um; 1e-3 um allowed).
TEST(DatumBallSimulate, ThermalTermsGiveEachReadingItsTime) {
  const BallCase timed = Table1a("effects:\n  - thermal_drift: {parameter: E_X0C, K_um: 8, tau_s: 1200}\n");
  const BallCase still = Table1a();
  auto a = SimulateDatumBall(timed.machine, timed.truth, DatumBallSimRequest{});
  auto b = SimulateDatumBall(still.machine, still.truth, DatumBallSimRequest{});
  ASSERT_TRUE(a.ok() && b.ok()) << a.status().ToString();
  EXPECT_TRUE(a->timed);
  EXPECT_NE(a->csv.find("B_deg,C_deg,x,y,z,t_s\n0,0,"), std::string::npos) << a->csv.substr(0, 120);
  EXPECT_NE(a->csv.find(",2100\n"), std::string::npos);
  for (std::size_t i = 0; i < a->readings.size(); ++i) {
    EXPECT_EQ(a->readings[i].rotary.t_s, 60.0 * static_cast<double>(i));
    auto cmd = kinematics::BallCentreCommand(timed.machine, timed.truth, a->readings[i].rotary,
                                             Eigen::Vector3d(200, 0.1, 300));
    ASSERT_TRUE(cmd.ok());
    EXPECT_EQ(a->readings[i].command_mm, *cmd);
  }
  EXPECT_EQ(a->readings.front().command_mm, b->readings.front().command_mm);
  const double moved_um = MmToUm((a->readings.back().command_mm - b->readings.back().command_mm).norm());
  EXPECT_NEAR(moved_um, 8.0 * (1.0 - std::exp(-2100.0 / 1200.0)), 1e-3);
}

TEST(DatumBallSimulate, BadRequestsNameTheFlagOrFile) {
  DatumBallSimRequest r;
  r.noise_um = -1.0;
  EXPECT_NE(r.Validate().message().find("--noise-um"), std::string::npos);
  r.noise_um = 0.0, r.seconds_per_position = NAN;
  EXPECT_NE(r.Validate().message().find("--seconds-per-position"), std::string::npos);
  const auto dir = std::filesystem::temp_directory_path() / "tpcal_ball_sim_test";
  std::filesystem::create_directories(dir);
  const std::string errors = (dir / "e.yaml").string();
  std::ofstream(errors) << "schema: tpcal.errors/1\nE_X0C_um: 10\nE_NOPE_um: 3\n";
  DatumBallSimRequest bad;
  bad.errors_path = errors;
  auto s = RunDatumBallSimulateStage(bad);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.status().file(), errors);
  EXPECT_EQ(s.status().line(), 3u) << s.status().ToString();
  bad.plan.c_step_deg = 0.0;
  std::ofstream(errors) << "schema: tpcal.errors/1\nE_X0C_um: 10\n";
  s = RunDatumBallSimulateStage(bad);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.status().message().find("C step"), std::string::npos) << s.status().ToString();
  std::filesystem::remove_all(dir);
}

// Coverage of the analytic u: 400 simulated tests (1 um noise, seeds 1..400), each identified.
// Per error, the fraction of tests whose estimate lies within 2 u of the truth follows
// Binomial(400, p) with p = P(|t_94| < 2) = 0.952 (dof 108 - 14): sd sqrt(p (1 - p) / 400) = 0.011;
// every error within 4 sd (0.043; 11 errors: a false alarm below 1e-3). A u 20 % too small gives
// p = 0.90 and fails.
TEST(DatumBallSimulate, AnalyticUncertaintyCoversTheTruthNinetyFivePercent) {
  const BallCase c = Table1a();
  constexpr int kTests = 400;
  constexpr double kP = 0.952;
  const double tol = 4.0 * std::sqrt(kP * (1.0 - kP) / kTests);
  kinematics::DatumBallOptions options;
  options.jackknife = false, options.monte_carlo_runs = 0;
  std::vector<std::string> names;
  std::vector<int> within;
  for (int t = 0; t < kTests; ++t) {
    DatumBallSimRequest request;
    request.noise_um = 1.0, request.seed = static_cast<std::uint64_t>(t + 1);
    auto sim = SimulateDatumBall(c.machine, c.truth, request);
    ASSERT_TRUE(sim.ok()) << sim.status().ToString();
    auto r = kinematics::IdentifyDatumBall(c.machine, sim->readings, options);
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    if (names.empty())
      for (const auto& p : r->parameters) names.push_back(p.name), within.push_back(0);
    for (std::size_t k = 0; k < names.size(); ++k) {
      const auto& p = r->parameters[k];
      within[k] += std::abs(p.value - DisplayValue(c.machine, c.truth, p.name)) <= 2.0 * p.u;
    }
  }
  int total = 0;
  for (std::size_t k = 0; k < names.size(); ++k) {
    const double fraction = static_cast<double>(within[k]) / kTests;
    total += within[k];
    std::printf("%-10s within 2u: %.3f\n", names[k].c_str(), fraction);
    EXPECT_NEAR(fraction, kP, tol) << names[k];
  }
  std::printf("all errors: %.4f of %zu within 2u (expected %.3f)\n",
              static_cast<double>(total) / (kTests * static_cast<double>(names.size())), kTests * names.size(), kP);
}

}  // namespace
}  // namespace tpcal::pipeline
