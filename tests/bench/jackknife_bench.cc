// Cost of the delete-one jackknife of the identification (issue 5: <= 3x the fit itself for a
// 10^5-point fit), a small driver printing ratios against the fit measured in the same run.
//
// Workload: the seed 002 turning piece probed densely (points per circle and levels per face
// from the command line; the default gives ~1e5 points), simulated with the Table 2 machining
// errors, 1 um CMM noise, identified with the Table 2 set:
//   fit                : Identify with the analytic covariance only (the baseline)
//   + jackknife points : closed-form delete-one-point updates (no refit)
//   + jackknife groups : and the delete-one-feature block downdates
//   naive refits       : Identify on n - 1 points for a few deleted points, extrapolated to n
// Usage: jackknife_bench [--points-per-circle N] [--levels L] [--refits R]
#include <time.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "kinematics/error_parameters.h"
#include "kinematics/identification.h"
#include "pipeline/identify_stage.h"
#include "testpieces/simulate_piece.h"

namespace {

using namespace tpcal;

double CpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double Time(const std::function<void()>& f) {
  const double t0 = CpuSeconds();
  f();
  return CpuSeconds() - t0;
}

}  // namespace

int main(int argc, char** argv) {
  int per_circle = 1024, levels = 8, refits = 3;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--points-per-circle")) per_circle = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--levels")) levels = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--refits")) refits = std::atoi(argv[i + 1]);
    else {
      std::fprintf(stderr, "usage: jackknife_bench [--points-per-circle N] [--levels L] [--refits R]\n");
      return 2;
    }
  }
  auto machine = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  testpieces::PieceConfig config;
  config.probing.points_per_circle = per_circle;
  config.probing.levels_per_face = levels;
  config.probing.points_per_hole = 32;
  config.probing.levels_per_hole = 4;
  auto piece = testpieces::MakeTestPiece(config, *machine);
  if (!piece.ok()) {
    std::fprintf(stderr, "%s\n", piece.status().ToString().c_str());
    return 1;
  }
  kinematics::ErrorState truth(*machine);
  const std::pair<const char*, double> table2[] = {
      {"dx_CR(0)", 12.4e-3}, {"dy_CR(0)", -16.8e-3}, {"alpha_CR(0)", -8.7e-6}, {"beta_CR(0)", -7e-6},
      {"dy_AR(-90)", 36.5e-3}, {"dz_AR(-90)", 28.6e-3}, {"dy_CA(-90)", -25.4e-3}, {"alpha_CR(-90)", 36.7e-6},
      {"gamma_CR(-90)", 1.6e-6}, {"beta_ZX", 3.5e-6}, {"alpha_ZY", 19.2e-6}};
  for (const auto& [n, v] : table2)
    if (!truth.SetParameter(*machine, n, v).ok()) return 1;
  testpieces::PieceSimOptions sim;
  sim.noise_um = 1.0;
  sim.seed = 3;
  auto simulated = testpieces::SimulatePiece(*piece, *machine, truth, sim);
  if (!simulated.ok()) {
    std::fprintf(stderr, "%s\n", simulated.status().ToString().c_str());
    return 1;
  }
  // Observations once (datum frame, association); the benchmark times the solver.
  pipeline::IdentifyStageOptions stage_options;
  stage_options.identify.primary = kinematics::UncertaintyMethod::kAnalytic;
  stage_options.identify.jackknife_groups = false;
  auto stage = pipeline::RunIdentifyStage(*piece, *machine, simulated->points, stage_options);
  if (!stage.ok()) {
    std::fprintf(stderr, "%s\n", stage.status().ToString().c_str());
    return 1;
  }
  const auto& obs = stage->observations.observations;
  kinematics::ErrorState base(*machine);
  auto active = kinematics::ActivateParameters(*machine, &base, stage->parameters);
  const std::size_t n = obs.size();

  auto run = [&](kinematics::UncertaintyMethod primary, bool groups, std::span<const kinematics::Observation> o) {
    kinematics::IdentifyOptions opt;
    opt.primary = primary;
    opt.jackknife_groups = groups;
    auto r = kinematics::Identify(*machine, base, *active, o, opt);
    if (!r.ok()) {
      std::fprintf(stderr, "%s\n", r.status().ToString().c_str());
      std::exit(1);
    }
  };
  const double t_fit = Time([&] { run(kinematics::UncertaintyMethod::kAnalytic, false, obs); });
  const double t_jk = Time([&] { run(kinematics::UncertaintyMethod::kJackknifePoints, false, obs); });
  const double t_jkg = Time([&] { run(kinematics::UncertaintyMethod::kJackknifePoints, true, obs); });
  std::vector<kinematics::Observation> subset(obs.begin() + 1, obs.end());
  double t_refits = 0.0;
  for (int r = 0; r < refits; ++r) {
    subset.assign(obs.begin(), obs.end());
    subset.erase(subset.begin() + static_cast<std::ptrdiff_t>((r * 7919u) % n));
    t_refits += Time([&] { run(kinematics::UncertaintyMethod::kAnalytic, false, subset); });
  }
  const double t_naive = t_refits / refits * static_cast<double>(n);
  std::printf("jackknife_bench: %zu points, %d parameters, process CPU time (all threads)\n", n, active->size());
  std::printf("%-34s %10.3f s   1.00x\n", "fit (analytic u only)", t_fit);
  std::printf("%-34s %10.3f s  %5.2fx of the fit\n", "fit + jackknife, delete one point", t_jk, t_jk / t_fit);
  std::printf("%-34s %10.3f s  %5.2fx of the fit\n", "fit + jackknife, points and groups", t_jkg, t_jkg / t_fit);
  std::printf("%-34s %10.1f s  %5.0fx of the fit (%d refits measured, extrapolated to n)\n",
              "naive delete-one refits", t_naive, t_naive / t_fit, refits);
  return 0;
}
