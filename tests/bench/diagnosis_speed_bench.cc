// Speed of one full diagnosis (tpcal diagnose: base fit, every candidate, leave-one-point-out
// cross-validation, aliasing tests, gap summaries) of the seed 002 turning piece, for the paper's
// 16-points-per-face plan and the dense plan (ProbingOptions::Dense()). Baseline measured in the
// same run: the identification stage alone (pipeline::RunIdentifyStage, Ceres LM with jackknife),
// which every calibration run already pays (not for the 10^5-point plan: minutes of jackknife).
// Issue 6 targets: < 1 s (16-point plan), < 10 s (10^5 points).
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <chrono>
#include <cstdio>

#include "kinematics/errors_yaml.h"
#include "pipeline/diagnosis/diagnosis.h"
#include "pipeline/identify_stage.h"
#include "testpieces/simulate_piece.h"

namespace {

using namespace tpcal;

struct Case {
  kinematics::MachineModel machine;
  testpieces::TestPiece piece;
  PointSet points;
};

// plan: 0 = the paper's (16 per circle), 1 = ProbingOptions::Dense(), 2 = ~10^5 points.
Case MakeCase(int plan) {
  auto m = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  testpieces::PieceConfig config;
  if (plan == 1) config.probing = testpieces::ProbingOptions::Dense();
  if (plan == 2) {
    config.probing = testpieces::ProbingOptions::Dense();
    config.probing.points_per_circle = 1400;
    config.probing.points_per_hole = 64;
    config.probing.levels_per_hole = 5;
  }
  auto piece = testpieces::MakeTestPiece(config, *m);
  auto errors = kinematics::ParseErrorState(
      "dx_CR(0)_um: 12.4\ndy_CR(0)_um: -16.8\ndy_AR(-90)_um: 36.5\ndz_AR(-90)_um: 28.6\nalpha_ZY_urad: 19.2\n"
      "effects:\n  - thermal_drift: {parameter: E_Y0A, K_um: 6, tau_s: 2400}\n",
      "<bench>", *m);
  testpieces::PieceSimOptions o;
  o.noise_um = 1.0;
  o.seed = 5;
  o.random_placement = true;
  auto sim = testpieces::SimulatePiece(*piece, *m, *errors, o);
  if (!m.ok() || !piece.ok() || !errors.ok() || !sim.ok()) {
    std::fprintf(stderr, "diagnosis_speed_bench: setup failed\n");
    std::exit(1);
  }
  return {*m, *piece, sim->points};
}

const Case& Paper() {
  static const Case c = MakeCase(0);
  return c;
}
const Case& Dense() {
  static const Case c = MakeCase(1);
  return c;
}
const Case& Dense1e5() {
  static const Case c = MakeCase(2);
  return c;
}

void BM_IdentifyStage(benchmark::State& state, const Case& (*get)()) {
  const Case& c = get();
  for (auto _ : state) {
    auto r = pipeline::RunIdentifyStage(c.piece, c.machine, c.points);
    benchmark::DoNotOptimize(r);
  }
  state.counters["points"] = static_cast<double>(c.points.size());
}

void BM_Diagnose(benchmark::State& state, const Case& (*get)()) {
  const Case& c = get();
  std::string verdict;
  for (auto _ : state) {
    auto r = pipeline::Diagnose(c.piece, c.machine, c.points);
    if (!r.ok()) {
      state.SkipWithError(r.status().ToString().c_str());
      return;
    }
    verdict = r->verdict.family;
    benchmark::DoNotOptimize(r);
  }
  state.counters["points"] = static_cast<double>(c.points.size());
  state.SetLabel("verdict " + verdict);
}

BENCHMARK_CAPTURE(BM_IdentifyStage, paper_16_per_face, &Paper)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Diagnose, paper_16_per_face, &Paper)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_IdentifyStage, dense, &Dense)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_Diagnose, dense, &Dense)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_Diagnose, dense_1e5, &Dense1e5)->Unit(benchmark::kMillisecond)->Iterations(1);

// Ratio line printed after the Google Benchmark table: diagnosis / identification, same run.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const auto& r : runs) {
      std::string name = r.benchmark_name();
      if (const auto slash = name.find("/iterations"); slash != std::string::npos) name.resize(slash);
      times_[name] = r.GetAdjustedRealTime();
    }
  }
  void Finalize() override {
    ConsoleReporter::Finalize();
    for (const char* plan : {"paper_16_per_face", "dense", "dense_1e5"}) {
      const auto d = times_.find(std::string("BM_Diagnose/") + plan);
      const auto i = times_.find(std::string("BM_IdentifyStage/") + plan);
      if (d != times_.end() && i == times_.end())  // 10^5 points: the identification stage is not run (minutes)
        std::printf("%s: diagnosis %.1f ms; target < 10 s (10^5 points)\n", plan, d->second);
      if (d != times_.end() && i != times_.end() && i->second > 0)
        std::printf("%s: diagnosis %.1f ms = %.2f x the identification stage (%.1f ms); target %s\n", plan, d->second,
                    d->second / i->second, i->second, std::string(plan) == "paper_16_per_face" ? "< 1 s" : "< 10 s (10^5 points)");
    }
  }

 private:
  std::map<std::string, double> times_;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  return 0;
}
