// Speed of the datum-ball identification (kinematics/datum_ball.h): a 3 x 36-position test
// (B = 0, +-30 deg, C every 10 deg; 108 readings, seed 001 Table 1(a) errors, 1 um noise), the
// 11 errors of the B/C table and the ball centre, with the defaults: analytic, jackknife and
// Monte Carlo u (200 runs); and without the Monte Carlo runs, for their cost. Baseline measured
// in the same run: one pass of the model over the readings (108 Newton centrings), the least any
// identification pays. Issue 19 target: < 50 ms.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <random>
#include <vector>

#include "core/units.h"
#include "kinematics/datum_ball.h"
#include "kinematics/errors_yaml.h"

namespace {

using namespace tpcal;

struct Case {
  kinematics::MachineModel machine;
  kinematics::ErrorState truth;
  std::vector<kinematics::BallReading> readings;
};

const Case& Test3x36() {
  static const Case c = [] {
    auto m = kinematics::MakeMachine(kinematics::MachineType::kBcTable);
    auto e = kinematics::ParseErrorState(
        "E_A(0Y)Z_urad: -34\nE_B(0X)Z_urad: 29\nE_C(0X)Y_urad: 17\nE_A0B_urad: -17\nE_C0B_urad: 75\n"
        "E_X0B_um: -12\nE_Z0B_um: 19\nE_A0C_urad: -87\nE_B0C_urad: 42\nE_X0C_um: 10\nE_Y0C_um: -15\n",
        "<bench>", *m);
    if (!m.ok() || !e.ok()) {
      std::fprintf(stderr, "datum_ball_bench: setup failed\n");
      std::exit(1);
    }
    std::mt19937_64 rng(5);
    std::normal_distribution<double> noise(0.0, 1.0);
    std::vector<kinematics::BallReading> readings;
    for (double b : {0.0, 30.0, -30.0})
      for (int c = 0; c < 360; c += 10) {
        kinematics::BallReading r;
        r.rotary.b_rad = DegToRad(b), r.rotary.c_rad = DegToRad(c);
        auto cmd = kinematics::BallCentreCommand(*m, *e, r.rotary, Eigen::Vector3d(200.0, 0.1, 300.0));
        if (!cmd.ok()) std::exit(1);
        r.command_mm = *cmd + UmToMm(1.0) * Eigen::Vector3d{noise(rng), noise(rng), noise(rng)};
        readings.push_back(r);
      }
    return Case{*m, *e, readings};
  }();
  return c;
}

void BM_CentringPass(benchmark::State& state) {
  const Case& c = Test3x36();
  for (auto _ : state)
    for (const auto& r : c.readings)
      benchmark::DoNotOptimize(kinematics::BallCentreCommand(c.machine, c.truth, r.rotary, Eigen::Vector3d(200, 0.1, 300)));
}
BENCHMARK(BM_CentringPass)->Unit(benchmark::kMillisecond);

void BM_Identify3x36(benchmark::State& state) {
  const Case& c = Test3x36();
  for (auto _ : state) {
    auto r = kinematics::IdentifyDatumBall(c.machine, c.readings);
    if (!r.ok()) state.SkipWithError("identification failed");
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_Identify3x36)->Unit(benchmark::kMillisecond);

void BM_Identify3x36NoMonteCarlo(benchmark::State& state) {
  const Case& c = Test3x36();
  kinematics::DatumBallOptions options;
  options.monte_carlo_runs = 0;
  for (auto _ : state) {
    auto r = kinematics::IdentifyDatumBall(c.machine, c.readings, options);
    if (!r.ok()) state.SkipWithError("identification failed");
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_Identify3x36NoMonteCarlo)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
