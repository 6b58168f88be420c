// Minimum-zone benchmarks (Google Benchmark), with ratios against baselines run in the same process:
//   flatness of 1e5 points: MinimumZoneFlatness vs CGAL Width_3 on all points (both exact; the
//     widths are printed and must agree);
//   circularity of 1e4 points: MinimumZoneCircularity vs the least-squares circle (FitCircle2) and
//     the exact minimum circumscribed circle (CGAL Min_circle_2).
// Data: synthetic CMM-like scans with fixed seeds, placed 500 mm from the origin.
// Usage: zone_bench [Google Benchmark flags]
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "fitting/circle_fit.h"
#include "fitting/minimum_zone.h"
#include "fitting/minimum_zone_exact.h"

namespace {

using namespace tpcal;
using namespace tpcal::fitting;

// A milled face 200 x 100 mm: 2 um noise, 3 um waviness along x, 5 um twist, 500 mm from origin.
const std::vector<Eigen::Vector3d>& FacePoints() {
  static const std::vector<Eigen::Vector3d> pts = [] {
    std::mt19937_64 rng(20240601);
    std::uniform_real_distribution<double> u(0, 1);
    std::normal_distribution<double> noise(0, 0.002);
    std::vector<Eigen::Vector3d> p;
    p.reserve(100000);
    for (int i = 0; i < 100000; ++i) {
      const double x = 200 * u(rng), y = 100 * u(rng);
      const double z = noise(rng) + 0.0015 * std::sin(x / 9.0) + 5e-7 * (x - 100) * (y - 50);
      p.emplace_back(500 + x, 500 + y, 500 + z);
    }
    return p;
  }();
  return pts;
}

// A turned bore, radius 40 mm: 1.5 um noise and 3-lobe form of 4 um, 500 mm from origin.
const std::vector<Eigen::Vector2d>& RingPoints() {
  static const std::vector<Eigen::Vector2d> pts = [] {
    std::mt19937_64 rng(20240602);
    std::uniform_real_distribution<double> a(0, 2 * M_PI);
    std::normal_distribution<double> noise(0, 0.0015);
    std::vector<Eigen::Vector2d> p;
    p.reserve(10000);
    for (int i = 0; i < 10000; ++i) {
      const double t = a(rng);
      const double r = 40 + 0.002 * std::cos(3 * t + 0.4) + noise(rng);
      p.emplace_back(500 + r * std::cos(t), 500 + r * std::sin(t));
    }
    return p;
  }();
  return pts;
}

std::map<std::string, double> g_value_mm;  // zone values, for the printed cross-check

void BM_FlatnessMinimumZone(benchmark::State& state) {
  const auto& p = FacePoints();
  for (auto _ : state) {
    auto r = MinimumZoneFlatness(p);
    if (!r.ok()) state.SkipWithError(r.status().ToString().c_str());
    g_value_mm["flatness_mz"] = r->width_mm;
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_FlatnessMinimumZone)->Unit(benchmark::kMillisecond);

void BM_FlatnessWidth3AllPoints(benchmark::State& state) {
  const auto& p = FacePoints();
  for (auto _ : state) {
    auto r = tpcal::fitting::internal::FlatnessWidth3AllPoints(p);
    if (!r.ok()) state.SkipWithError(r.status().ToString().c_str());
    g_value_mm["flatness_width3"] = *r;
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_FlatnessWidth3AllPoints)->Unit(benchmark::kMillisecond)->Iterations(2);

void BM_CircularityMinimumZone(benchmark::State& state) {
  const auto& p = RingPoints();
  for (auto _ : state) {
    auto r = MinimumZoneCircularity(p);
    if (!r.ok()) state.SkipWithError(r.status().ToString().c_str());
    g_value_mm["circularity_mz"] = r->width_mm;
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_CircularityMinimumZone)->Unit(benchmark::kMillisecond);

void BM_CircleLeastSquares(benchmark::State& state) {
  const auto& p = RingPoints();
  FitOptions o;
  o.compute_covariance = false;
  o.keep_residuals = false;
  for (auto _ : state) {
    auto r = FitCircle2(p, o);
    if (!r.ok()) state.SkipWithError(r.status().ToString().c_str());
    g_value_mm["circularity_ls_form"] = r->stats.form_mm;
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_CircleLeastSquares)->Unit(benchmark::kMillisecond);

void BM_MinimumCircumscribedCircle(benchmark::State& state) {
  const auto& p = RingPoints();
  for (auto _ : state) {
    auto r = MinimumCircumscribedCircle(p);
    if (!r.ok()) state.SkipWithError(r.status().ToString().c_str());
    g_value_mm["circularity_mcc_ptv"] = r->peak_to_valley_mm;
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_MinimumCircumscribedCircle)->Unit(benchmark::kMillisecond);

// Keeps each benchmark's real time per iteration (s) for the ratio table.
class RecordingReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      if (r.run_type == Run::RT_Iteration && r.iterations > 0) {
        seconds_[r.benchmark_name()] = r.real_accumulated_time / static_cast<double>(r.iterations);
        cpu_seconds_[r.benchmark_name()] = r.cpu_accumulated_time / static_cast<double>(r.iterations);
      }
    }
    ConsoleReporter::ReportRuns(runs);
  }
  double Seconds(const std::string& name) const { return Get(seconds_, name); }
  double CpuSeconds(const std::string& name) const { return Get(cpu_seconds_, name); }

 private:
  static double Get(const std::map<std::string, double>& m, const std::string& name) {
    auto it = m.find(name);
    return it == m.end() ? std::nan("") : it->second;
  }
  std::map<std::string, double> seconds_, cpu_seconds_;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  RecordingReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();

  auto value = [](const char* k) { return g_value_mm.count(k) ? g_value_mm[k] : std::nan(""); };
  const double t_mz = reporter.Seconds("BM_FlatnessMinimumZone");
  const double t_w3 = reporter.Seconds("BM_FlatnessWidth3AllPoints/iterations:2");
  const double c_mz = reporter.CpuSeconds("BM_FlatnessMinimumZone");
  const double c_w3 = reporter.CpuSeconds("BM_FlatnessWidth3AllPoints/iterations:2");
  fmt::print("\nflatness, 1e5 points: minimum zone {:.1f} ms, Width_3 on all points {:.1f} ms, speed-up x{:.0f} "
             "(CPU time: {:.1f} ms vs {:.1f} ms, x{:.0f})\n",
             1e3 * t_mz, 1e3 * t_w3, t_w3 / t_mz, 1e3 * c_mz, 1e3 * c_w3, c_w3 / c_mz);
  fmt::print("  width: minimum zone {:.12f} mm, Width_3 {:.12f} mm (must agree: both exact)\n", value("flatness_mz"),
             value("flatness_width3"));
  const double t_c = reporter.Seconds("BM_CircularityMinimumZone");
  const double t_ls = reporter.Seconds("BM_CircleLeastSquares");
  const double t_mcc = reporter.Seconds("BM_MinimumCircumscribedCircle");
  fmt::print("circularity, 1e4 points: minimum zone {:.1f} ms = x{:.1f} least squares ({:.1f} ms), x{:.1f} "
             "Min_circle_2 ({:.1f} ms)\n",
             1e3 * t_c, t_c / t_ls, 1e3 * t_ls, t_c / t_mcc, 1e3 * t_mcc);
  fmt::print("  zone: minimum zone {:.6f} mm <= least-squares form {:.6f} mm, about MCC centre {:.6f} mm\n",
             value("circularity_mz"), value("circularity_ls_form"), value("circularity_mcc_ptv"));
  return 0;
}
