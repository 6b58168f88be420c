// Least-squares fitting benchmarks (Google Benchmark). Prints, after the usual table, ratios
// measured in the same run:
//  1. FitPlane and FitCircle2 on 10^6 points against one streaming pass over the same
//     points (the sum of all coordinates, vectorised by Eigen): target <= 4x.
//  2. PCL 1.13 RANSAC + refine (SACSegmentation, optimize coefficients on; SACMODEL_PLANE,
//     SACMODEL_CIRCLE3D, and SACMODEL_CYLINDER from normals) against FitPlane, FitCircle3 and
//     FitCylinder (no hint) on the same 10^4 noisy points: time ratio and errors against the
//     certified least-squares answer (fitting/reference_data.h, deviations 5 um RMS), so an
//     exact LS fit has zero error and any error is the method's or its arithmetic's.
//     PCL gets float coordinates (PointXYZ) 1000 mm from the origin, as a CMM frame gives them,
//     and, for the cylinder, the exact surface normals.
// Ratios use CPU time (the build machines are shared; wall time is in the table).
// Usage: fit_bench [--benchmark_filter=REGEX] [--benchmark_min_time=SECONDS]
#include <benchmark/benchmark.h>
#include <pcl/ModelCoefficients.h>
#include <pcl/console/print.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/segmentation/sac_segmentation.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "core/units.h"
#include "fitting/circle_fit.h"
#include "fitting/cylinder_fit.h"
#include "fitting/plane_fit.h"
#include "fitting/reference_data.h"

namespace {

using namespace tpcal;
using namespace tpcal::fitting;

constexpr std::size_t kLarge = 1000000;  // streaming comparison
constexpr std::size_t kPcl = 10000;      // PCL comparison
constexpr double kDeviation_mm = 0.005;  // RMS of the certified residuals

// Certified data sets, built once.
const ReferenceSet<Plane, Eigen::Vector3d>& PlaneData(std::size_t n) {
  static std::map<std::size_t, ReferenceSet<Plane, Eigen::Vector3d>> cache;
  auto it = cache.find(n);
  if (it == cache.end()) {
    std::mt19937_64 rng(1001);
    ReferenceOptions o;
    o.n_points = n;
    o.length_mm = 200.0;
    o.width_mm = 150.0;
    o.deviation_rms_mm = kDeviation_mm;
    it = cache.emplace(n, *MakeReferencePlane(*MakePlane({1000, 800, 600}, {0.1, -0.2, 1.0}), o, rng)).first;
  }
  return it->second;
}

const ReferenceSet<Circle2, Eigen::Vector2d>& Circle2Data() {
  static const auto data = [] {
    std::mt19937_64 rng(1002);
    ReferenceOptions o;
    o.n_points = kLarge;
    o.deviation_rms_mm = kDeviation_mm;
    return *MakeReferenceCircle2({{1000.0, -700.0}, 50.0}, o, rng);
  }();
  return data;
}

const ReferenceSet<Circle3, Eigen::Vector3d>& Circle3Data() {
  static const auto data = [] {
    std::mt19937_64 rng(1003);
    ReferenceOptions o;
    o.n_points = kPcl;
    o.deviation_rms_mm = kDeviation_mm;
    return *MakeReferenceCircle3(*MakeCircle3({1000, 800, 600}, {0.2, 0.1, 1.0}, 50.0), o, rng);
  }();
  return data;
}

const ReferenceSet<Cylinder, Eigen::Vector3d>& CylinderData() {
  static const auto data = [] {
    std::mt19937_64 rng(1004);
    ReferenceOptions o;
    o.n_points = kPcl;
    o.length_mm = 60.0;
    o.deviation_rms_mm = kDeviation_mm;
    return *MakeReferenceCylinder(*MakeCylinder({1000, 800, 600}, {0.3, -0.2, 1.0}, 25.0), o, rng);
  }();
  return data;
}

pcl::PointCloud<pcl::PointXYZ>::Ptr ToPcl(const std::vector<Eigen::Vector3d>& p) {
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->reserve(p.size());
  for (const auto& x : p) cloud->push_back(pcl::PointXYZ(static_cast<float>(x.x()), static_cast<float>(x.y()),
                                                          static_cast<float>(x.z())));
  return cloud;
}

double Angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return std::atan2(a.cross(b).norm(), std::abs(a.dot(b))); }

Eigen::Vector3d Centroid(const std::vector<Eigen::Vector3d>& p) {
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  for (const auto& x : p) s += x;
  return s / static_cast<double>(p.size());
}

void SetErrors(benchmark::State& state, double pos_mm, double dir_rad, double size_mm) {
  state.counters["pos_err_um"] = MmToUm(pos_mm);
  state.counters["dir_err_urad"] = RadToUrad(dir_rad);
  state.counters["size_err_um"] = MmToUm(size_mm);
}

// ---- 1. streaming comparison on 10^6 points ----

void BM_SumPass3(benchmark::State& state) {
  const auto& p = PlaneData(kLarge).points_mm;
  for (auto _ : state) {
    benchmark::DoNotOptimize(Eigen::Map<const Eigen::ArrayXd>(p.data()->data(), static_cast<Eigen::Index>(3 * p.size())).sum());
  }
}
BENCHMARK(BM_SumPass3)->Unit(benchmark::kMillisecond);

void BM_FitPlane1e6(benchmark::State& state) {
  const auto& d = PlaneData(kLarge);
  for (auto _ : state) {
    auto fit = FitPlane(d.points_mm);
    benchmark::DoNotOptimize(fit);
  }
}
BENCHMARK(BM_FitPlane1e6)->Unit(benchmark::kMillisecond);

void BM_SumPass2(benchmark::State& state) {
  const auto& p = Circle2Data().points_mm;
  for (auto _ : state) {
    benchmark::DoNotOptimize(Eigen::Map<const Eigen::ArrayXd>(p.data()->data(), static_cast<Eigen::Index>(2 * p.size())).sum());
  }
}
BENCHMARK(BM_SumPass2)->Unit(benchmark::kMillisecond);

// The same stream with one square root per point (sum of distances to a point): the least
// work any geometric (orthogonal distance) evaluation of a circle does per pass.
void BM_DistancePass2(benchmark::State& state) {
  const auto& p = Circle2Data().points_mm;
  const Eigen::Map<const Eigen::Matrix2Xd> m(p.data()->data(), 2, static_cast<Eigen::Index>(p.size()));
  const Eigen::Vector2d c = Circle2Data().truth.center_mm;
  for (auto _ : state) benchmark::DoNotOptimize((m.colwise() - c).colwise().norm().sum());
}
BENCHMARK(BM_DistancePass2)->Unit(benchmark::kMillisecond);

void BM_FitCircle2_1e6(benchmark::State& state) {
  const auto& d = Circle2Data();
  Result<FitResult<Circle2>> fit = Status(StatusCode::kInternal, "not run");
  for (auto _ : state) {
    fit = FitCircle2(d.points_mm);
    benchmark::DoNotOptimize(fit);
  }
  if (fit.ok()) {
    SetErrors(state, (fit->feature.center_mm - d.truth.center_mm).norm(), 0.0,
              std::abs(fit->feature.radius_mm - d.truth.radius_mm));
    state.counters["iterations"] = fit->iterations;
  }
}
BENCHMARK(BM_FitCircle2_1e6)->Unit(benchmark::kMillisecond);

// ---- 2. PCL RANSAC + refine against the least-squares fits, 10^4 points ----

void BM_TpcalPlane(benchmark::State& state) {
  const auto& d = PlaneData(kPcl);
  Result<FitResult<Plane>> fit = Status(StatusCode::kInternal, "not run");
  for (auto _ : state) {
    fit = FitPlane(d.points_mm);
    benchmark::DoNotOptimize(fit);
  }
  const Eigen::Vector3d c = Centroid(d.points_mm);
  if (fit.ok()) SetErrors(state, std::abs(fit->feature.SignedDistance(c) - d.truth.SignedDistance(c)),
                          Angle(fit->feature.normal, d.truth.normal), 0.0);
}
BENCHMARK(BM_TpcalPlane)->Unit(benchmark::kMillisecond);

void BM_PclPlane(benchmark::State& state) {
  const auto& d = PlaneData(kPcl);
  const auto cloud = ToPcl(d.points_mm);
  pcl::ModelCoefficients coef;
  for (auto _ : state) {
    pcl::SACSegmentation<pcl::PointXYZ> seg;
    seg.setModelType(pcl::SACMODEL_PLANE);
    seg.setMethodType(pcl::SAC_RANSAC);
    seg.setDistanceThreshold(5.0 * kDeviation_mm);
    seg.setMaxIterations(1000);
    seg.setOptimizeCoefficients(true);
    seg.setInputCloud(cloud);
    pcl::PointIndices inliers;
    seg.segment(inliers, coef);
    benchmark::DoNotOptimize(coef);
  }
  if (coef.values.size() == 4) {
    const Eigen::Vector3d n(coef.values[0], coef.values[1], coef.values[2]);
    const Eigen::Vector3d c = Centroid(d.points_mm);
    // Distance, at the data centroid, between the PCL plane and the certified one.
    const Eigen::Vector3d on_truth = c - d.truth.SignedDistance(c) * d.truth.normal;
    SetErrors(state, std::abs(n.dot(on_truth) + coef.values[3]) / n.norm(), Angle(n, d.truth.normal), 0.0);
  }
}
BENCHMARK(BM_PclPlane)->Unit(benchmark::kMillisecond);

void BM_TpcalCircle3(benchmark::State& state) {
  const auto& d = Circle3Data();
  Result<FitResult<Circle3>> fit = Status(StatusCode::kInternal, "not run");
  for (auto _ : state) {
    fit = FitCircle3(d.points_mm);
    benchmark::DoNotOptimize(fit);
  }
  if (fit.ok()) SetErrors(state, (fit->feature.center_mm - d.truth.center_mm).norm(), Angle(fit->feature.axis, d.truth.axis),
                          std::abs(fit->feature.radius_mm - d.truth.radius_mm));
}
BENCHMARK(BM_TpcalCircle3)->Unit(benchmark::kMillisecond);

void BM_PclCircle3D(benchmark::State& state) {
  const auto& d = Circle3Data();
  const auto cloud = ToPcl(d.points_mm);
  pcl::ModelCoefficients coef;
  for (auto _ : state) {
    pcl::SACSegmentation<pcl::PointXYZ> seg;
    seg.setModelType(pcl::SACMODEL_CIRCLE3D);
    seg.setMethodType(pcl::SAC_RANSAC);
    seg.setDistanceThreshold(5.0 * kDeviation_mm);
    seg.setRadiusLimits(0.0, 2.0 * d.truth.radius_mm);
    seg.setMaxIterations(1000);
    seg.setOptimizeCoefficients(true);
    seg.setInputCloud(cloud);
    pcl::PointIndices inliers;
    seg.segment(inliers, coef);
    benchmark::DoNotOptimize(coef);
  }
  if (coef.values.size() == 7) {
    const Eigen::Vector3d c(coef.values[0], coef.values[1], coef.values[2]);
    const Eigen::Vector3d n(coef.values[4], coef.values[5], coef.values[6]);
    SetErrors(state, (c - d.truth.center_mm).norm(), Angle(n, d.truth.axis), std::abs(coef.values[3] - d.truth.radius_mm));
  }
}
BENCHMARK(BM_PclCircle3D)->Unit(benchmark::kMillisecond);

void BM_TpcalCylinder(benchmark::State& state) {
  const auto& d = CylinderData();
  Result<FitResult<Cylinder>> fit = Status(StatusCode::kInternal, "not run");
  for (auto _ : state) {
    fit = FitCylinder(d.points_mm);
    benchmark::DoNotOptimize(fit);
  }
  if (fit.ok()) {
    SetErrors(state, Distance(Line3{d.truth.point_mm, d.truth.axis}, fit->feature.point_mm),
              Angle(fit->feature.axis, d.truth.axis), std::abs(fit->feature.radius_mm - d.truth.radius_mm));
  }
}
BENCHMARK(BM_TpcalCylinder)->Unit(benchmark::kMillisecond);

void BM_PclCylinder(benchmark::State& state) {
  const auto& d = CylinderData();
  const auto cloud = ToPcl(d.points_mm);
  auto normals = std::make_shared<pcl::PointCloud<pcl::Normal>>();
  for (const auto& p : d.points_mm) {
    const Eigen::Vector3d r = p - d.truth.point_mm;
    const Eigen::Vector3d n = (r - d.truth.axis.dot(r) * d.truth.axis).normalized();
    normals->push_back(pcl::Normal(static_cast<float>(n.x()), static_cast<float>(n.y()), static_cast<float>(n.z())));
  }
  pcl::ModelCoefficients coef;
  for (auto _ : state) {
    pcl::SACSegmentationFromNormals<pcl::PointXYZ, pcl::Normal> seg;
    seg.setModelType(pcl::SACMODEL_CYLINDER);
    seg.setMethodType(pcl::SAC_RANSAC);
    seg.setNormalDistanceWeight(0.1);
    seg.setDistanceThreshold(5.0 * kDeviation_mm);
    seg.setRadiusLimits(0.0, 2.0 * d.truth.radius_mm);
    seg.setMaxIterations(1000);
    seg.setOptimizeCoefficients(true);
    seg.setInputCloud(cloud);
    seg.setInputNormals(normals);
    pcl::PointIndices inliers;
    seg.segment(inliers, coef);
    benchmark::DoNotOptimize(coef);
  }
  if (coef.values.size() == 7) {
    const Eigen::Vector3d p(coef.values[0], coef.values[1], coef.values[2]);
    const Eigen::Vector3d a = Eigen::Vector3d(coef.values[3], coef.values[4], coef.values[5]).normalized();
    // Axis offset at the foot of the data centroid on the true axis.
    const Eigen::Vector3d c = Centroid(d.points_mm);
    const Eigen::Vector3d foot = d.truth.point_mm + d.truth.axis.dot(c - d.truth.point_mm) * d.truth.axis;
    SetErrors(state, a.cross(foot - p).norm(), Angle(a, d.truth.axis), std::abs(coef.values[6] - d.truth.radius_mm));
  }
}
BENCHMARK(BM_PclCylinder)->Unit(benchmark::kMillisecond);

// Console output plus a record of each run for the ratio table.
class RecordingReporter : public benchmark::ConsoleReporter {
 public:
  struct Entry {
    double time_ms = 0;  // CPU time: the machines this runs on are shared, wall time is noisy
    std::map<std::string, double> counters;
  };
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const auto& r : runs) {
      Entry e;
      e.time_ms = r.GetAdjustedCPUTime();  // every benchmark here reports in ms
      for (const auto& [k, c] : r.counters) e.counters[k] = c.value;
      entries_[r.benchmark_name()] = e;
    }
    ConsoleReporter::ReportRuns(runs);
  }
  void PrintRatios() const {
    std::printf("\nRatios measured in this run (CPU time):\n");
    Ratio("LS plane, 1e6 points", "BM_FitPlane1e6", "BM_SumPass3", "one streaming pass (coordinate sum)");
    Ratio("LS circle, 1e6 points", "BM_FitCircle2_1e6", "BM_SumPass2", "one streaming pass (coordinate sum)");
    Ratio("LS circle, 1e6 points", "BM_FitCircle2_1e6", "BM_DistancePass2", "one pass of |p - c| (a sqrt per point)");
    std::printf("\nPCL 1.13 RANSAC+refine vs tpcal LS, %zu points, certified data (deviations %.0f um RMS):\n", kPcl,
                MmToUm(kDeviation_mm));
    std::printf("  %-9s %10s %10s %8s | %-38s | %-38s\n", "feature", "PCL ms", "tpcal ms", "PCL/tpcal", "PCL error pos um / dir urad / size um",
                "tpcal error pos um / dir urad / size um");
    Compare("plane", "BM_PclPlane", "BM_TpcalPlane");
    Compare("circle", "BM_PclCircle3D", "BM_TpcalCircle3");
    Compare("cylinder", "BM_PclCylinder", "BM_TpcalCylinder");
  }

 private:
  const Entry* Find(const std::string& name) const {
    auto it = entries_.find(name);
    return it == entries_.end() ? nullptr : &it->second;
  }
  void Ratio(const char* what, const std::string& num, const std::string& den, const char* baseline) const {
    const Entry* a = Find(num);
    const Entry* b = Find(den);
    if (a == nullptr || b == nullptr) return;
    std::printf("  %-22s %8.2f ms vs %-40s %6.2f ms: ratio %.2f (target <= 4)\n", what, a->time_ms, baseline,
                b->time_ms, a->time_ms / b->time_ms);
  }
  static double Get(const Entry& e, const char* k) {
    auto it = e.counters.find(k);
    return it == e.counters.end() ? NAN : it->second;
  }
  void Compare(const char* what, const std::string& pcl_name, const std::string& ours_name) const {
    const Entry* p = Find(pcl_name);
    const Entry* o = Find(ours_name);
    if (p == nullptr || o == nullptr) return;
    std::printf("  %-9s %10.3f %10.3f %8.1f | %10.3g / %10.3g / %10.3g   | %10.2g / %10.2g / %10.2g\n", what,
                p->time_ms, o->time_ms, p->time_ms / o->time_ms, Get(*p, "pos_err_um"), Get(*p, "dir_err_urad"),
                Get(*p, "size_err_um"), Get(*o, "pos_err_um"), Get(*o, "dir_err_urad"), Get(*o, "size_err_um"));
  }
  std::map<std::string, Entry> entries_;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  RecordingReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.PrintRatios();
  benchmark::Shutdown();
  return 0;
}
