// The virtual probing test of artifacts (pipeline/probe_artifacts_simulate_stage.h). Truth: seed
// 000's plan on the nominal A/C table with seed 000's three columns, and the errors of
// kProbeSimErrorsYaml (a C table shift E_X0C 10 um, a tilt E_A0C -20 urad, E_AA over A as a
// table). What each touch must be is kinematics::SimulateTouch under the same errors (tested on
// its own in kinematics/probe_touch_test.cc); this test pins the stage's bookkeeping: plan order,
// the noise draws, pre-travel and radius passed through, the file's rounding, times, truth, errors.
#include "pipeline/probe_artifacts_simulate_stage.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "core/portable_random.h"
#include "core/units.h"
#include "kinematics/errors_yaml.h"
#include "kinematics/table_poses.h"

namespace tpcal::pipeline {
namespace {

constexpr double kProbeSimFileRounding_mm = 5e-5;  // the file's 4 decimals
constexpr double kProbeSimArithmetic_mm = 1e-12;   // a shift along a unit vector of a ~150 mm point

const char kProbeSimErrorsYaml[] =
    "schema: tpcal.errors/1\nE_X0C_um: 10\nE_A0C_urad: -20\neffects:\n"
    "  - rotary_error_motion: {symbol: E_AA, positions_deg: [-90, -60, -30, 0], values_urad: [35, 22, 10, 0],"
    " interpolation: linear}\n";

struct ProbeSimCase {
  kinematics::MachineModel machine;
  kinematics::ErrorState errors;
};

ProbeSimCase ProbeSimMachine(const std::string& yaml = kProbeSimErrorsYaml) {
  auto m = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  EXPECT_TRUE(m.ok());
  auto e = kinematics::ParseErrorState(yaml, "<test>", *m);
  EXPECT_TRUE(e.ok()) << e.status().ToString();
  return {*m, *e};
}

// Touch i is SimulateTouch at planned touch i plus noise_um x the i-th StandardNormal of
// std::mt19937_64(seed) along the plan's approach (what the truth file says); the file holds
// those contacts to 4 decimals, in plan order, and is not a plan.
TEST(ProbeArtifactsSimulate, TouchesAreTheVirtualTouchesPlusTheStatedNoise) {
  const ProbeSimCase c = ProbeSimMachine();
  ProbeArtifactsSimRequest noisy;
  noisy.noise_um = 0.3, noisy.seed = 1, noisy.truth = true;
  auto sim = SimulateProbeArtifacts(c.machine, c.errors, kinematics::Seed000Artifacts(), noisy);
  ASSERT_TRUE(sim.ok()) << sim.status().ToString();
  ASSERT_EQ(sim->touches.size(), sim->plan.touches.size());
  ASSERT_GT(sim->touches.size(), 100u);
  std::mt19937_64 rng(1);
  for (std::size_t i = 0; i < sim->touches.size(); ++i) {
    const testpieces::PlannedTouch& p = sim->plan.touches[i];
    const kinematics::ProbeTouch& t = sim->touches[i];
    EXPECT_EQ(t.artifact, p.artifact);
    EXPECT_EQ(t.face, p.face);
    EXPECT_EQ(t.approach, p.approach);
    const kinematics::FaceGeometry face = kinematics::FaceOf(sim->plan.artifacts.boxes[p.artifact], p.face);
    auto clean = kinematics::SimulateTouch(c.machine, c.errors, p.rotary, face, p.target_part_mm, {});
    ASSERT_TRUE(clean.ok());
    EXPECT_EQ(t.contact_mm, *clean + UmToMm(0.3 * StandardNormal(rng)) * p.approach) << i;
  }
  auto file = ParseProbePoints(sim->csv, "sim.csv");
  ASSERT_TRUE(file.ok()) << file.status().ToString();
  EXPECT_FALSE(file->is_plan);
  EXPECT_FALSE(file->has_t);
  ASSERT_EQ(file->rows.size(), sim->touches.size());
  for (std::size_t i = 0; i < file->rows.size(); ++i) {
    EXPECT_LE((file->rows[i].point_mm - sim->touches[i].contact_mm).cwiseAbs().maxCoeff(), kProbeSimFileRounding_mm);
    EXPECT_LE((file->rows[i].approach - sim->touches[i].approach).cwiseAbs().maxCoeff(), 1e-12);
  }
  EXPECT_NE(sim->truth_yaml.find("instrument: probe_artifacts\n"), std::string::npos);
  EXPECT_NE(sim->truth_yaml.find("seed: 1 "), std::string::npos);
  EXPECT_NE(sim->truth_yaml.find("noise_um: 0.29999999999999999 "), std::string::npos) << sim->truth_yaml;
  EXPECT_NE(sim->truth_yaml.find("E_X0C_um: 10"), std::string::npos) << sim->truth_yaml;
  EXPECT_NE(sim->truth_yaml.find("symbol: E_AA"), std::string::npos) << sim->truth_yaml;
  EXPECT_NE(sim->truth_yaml.find("artifacts:\n  "), std::string::npos) << sim->truth_yaml;
}

// End to end: the noise-free touches, fitted as table poses (kinematics::FitTablePoses), give the
// exact table pose error of the stated errors relative to A = C = 0 (kinematics::TablePoseError)
// at every pose: every error here moves the table rigidly, so only the fit's first order is off:
// (35 urad)^2 x 150 mm = 2e-4 um, and a rotation over a 30 mm lever arm 7e-3 urad; 0.02 allowed.
TEST(ProbeArtifactsSimulate, FittedTablePosesAreTheStatedErrors) {
  const ProbeSimCase c = ProbeSimMachine();
  auto sim = SimulateProbeArtifacts(c.machine, c.errors, kinematics::Seed000Artifacts(), ProbeArtifactsSimRequest{});
  ASSERT_TRUE(sim.ok()) << sim.status().ToString();
  auto fit = kinematics::FitTablePoses(c.machine, sim->plan.artifacts, sim->touches);
  ASSERT_TRUE(fit.ok()) << fit.status().ToString();
  ASSERT_EQ(fit->poses.size(), 24u);
  int compared = 0;
  for (const kinematics::TablePose& pose : fit->poses) {
    kinematics::AxisState rotary;
    rotary.a_rad = DegToRad(pose.a_deg), rotary.c_rad = DegToRad(pose.c_deg);
    const kinematics::Vector6d truth = kinematics::TablePoseError(c.machine, c.errors, rotary, kinematics::AxisState{});
    for (int k = 0; k < 6; ++k) {
      if (!pose.identifiable[k]) continue;
      ++compared;
      EXPECT_NEAR(pose.value(k), truth(k), 0.02) << "A " << pose.a_deg << " C " << pose.c_deg << " "
                                                 << kinematics::kPoseComponents[k];
    }
  }
  EXPECT_GT(compared, 100);
}

// Pre-travel p0 moves every reading by p0 along its approach (kinematics/probe_touch.h), the same
// Newton solution shifted: to rounding. Without noise the same seed changes nothing.
TEST(ProbeArtifactsSimulate, PretravelMovesEveryReadingAlongItsApproach) {
  const ProbeSimCase c = ProbeSimMachine();
  ProbeArtifactsSimRequest plain, delayed;
  delayed.touch.pretravel_um = 2.0;
  delayed.seed = 99;
  auto a = SimulateProbeArtifacts(c.machine, c.errors, kinematics::Seed000Artifacts(), plain);
  auto b = SimulateProbeArtifacts(c.machine, c.errors, kinematics::Seed000Artifacts(), delayed);
  ASSERT_TRUE(a.ok() && b.ok());
  ASSERT_EQ(a->touches.size(), b->touches.size());
  for (std::size_t i = 0; i < a->touches.size(); ++i) {
    const Eigen::Vector3d moved = b->touches[i].contact_mm - a->touches[i].contact_mm;
    EXPECT_LE((moved - UmToMm(2.0) * a->touches[i].approach).cwiseAbs().maxCoeff(), kProbeSimArithmetic_mm) << i;
  }
}

// Thermal terms: touch i at t_s = 10 i s (the default), and the file has a t_s column.
TEST(ProbeArtifactsSimulate, ThermalTermsGiveEachTouchItsTime) {
  const ProbeSimCase c =
      ProbeSimMachine(std::string(kProbeSimErrorsYaml) + "  - thermal_drift: {parameter: E_X0C, K_um: 8, tau_s: 1200}\n");
  auto sim = SimulateProbeArtifacts(c.machine, c.errors, kinematics::Seed000Artifacts(), ProbeArtifactsSimRequest{});
  ASSERT_TRUE(sim.ok()) << sim.status().ToString();
  EXPECT_TRUE(sim->timed);
  auto file = ParseProbePoints(sim->csv, "sim.csv");
  ASSERT_TRUE(file.ok()) << file.status().ToString();
  ASSERT_TRUE(file->has_t);
  for (std::size_t i = 0; i < sim->touches.size(); ++i) {
    EXPECT_EQ(sim->touches[i].rotary.t_s, 10.0 * static_cast<double>(i));
    EXPECT_EQ(file->rows[i].t_s, 10.0 * static_cast<double>(i));
  }
}

TEST(ProbeArtifactsSimulate, BadRequestsNameTheFlagOrFile) {
  ProbeArtifactsSimRequest r;
  r.noise_um = -1.0;
  EXPECT_NE(r.Validate().message().find("--noise-um"), std::string::npos);
  r.noise_um = 0.0, r.touch.probe_radius_mm = 0.0;
  EXPECT_NE(r.Validate().message().find("--probe-radius-mm"), std::string::npos);
  r.touch.probe_radius_mm = 3.0, r.touch.pretravel_lobing_um = NAN;
  EXPECT_NE(r.Validate().message().find("--pretravel-lobing-um"), std::string::npos);
  r.touch.pretravel_lobing_um = 0.0, r.seconds_per_touch = -1.0;
  EXPECT_NE(r.Validate().message().find("--seconds-per-touch"), std::string::npos);

  const auto dir = std::filesystem::temp_directory_path() / "tpcal_probe_sim_stage_test";
  std::filesystem::create_directories(dir);
  const std::string errors = (dir / "e.yaml").string();
  const std::string artifacts = (dir / "a.yaml").string();
  std::ofstream(errors) << "schema: tpcal.errors/1\nE_X0C_um: 10\nE_NOPE_um: 3\n";
  ProbeArtifactsSimRequest bad;
  bad.errors_path = errors;
  auto s = RunProbeArtifactsSimulateStage(bad);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.status().file(), errors);
  EXPECT_EQ(s.status().line(), 3u) << s.status().ToString();
  std::ofstream(errors) << "schema: tpcal.errors/1\nE_X0C_um: 10\n";
  std::ofstream(artifacts) << "artifacts:\n  - {name: \"1\", base_centre_mm: [100, 0, 0], size_mm: [30, 30]}\n";
  bad.artifacts_path = artifacts;
  s = RunProbeArtifactsSimulateStage(bad);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.status().file(), artifacts) << s.status().ToString();
  EXPECT_EQ(s.status().line(), 2u) << s.status().ToString();
  bad.artifacts_path.clear();
  bad.plan.c_step_deg = 0.0;
  s = RunProbeArtifactsSimulateStage(bad);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.status().file(), "tpcal simulate") << s.status().ToString();
  EXPECT_NE(s.status().message().find("c_step_deg"), std::string::npos) << s.status().ToString();
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace tpcal::pipeline
