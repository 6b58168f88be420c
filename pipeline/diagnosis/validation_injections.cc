#include "pipeline/diagnosis/validation_injections.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <vector>

#include "pipeline/diagnosis/internal/validation_draws.h"

namespace tpcal::pipeline {
namespace {

using internal::Pick;
using internal::Uniform;

// The indices of `feature`'s points, nearest `centre` first.
std::vector<int> NearestOnFeature(const testpieces::ProbingPlan& plan, const std::string& feature,
                                  const Eigen::Vector3d& centre) {
  std::vector<int> idx;
  for (int i = 0; i < static_cast<int>(plan.points.size()); ++i)
    if (plan.points[i].feature == feature) idx.push_back(i);
  std::sort(idx.begin(), idx.end(), [&](int a, int b) {
    return (plan.points[a].point_part_mm - centre).squaredNorm() < (plan.points[b].point_part_mm - centre).squaredNorm();
  });
  return idx;
}

}  // namespace

Eigen::VectorXd OutlierOffsets(const testpieces::ProbingPlan& plan, std::mt19937_64& rng, std::string* detail) {
  const int n = static_cast<int>(plan.points.size());
  Eigen::VectorXd off = Eigen::VectorXd::Zero(n);
  const int m = std::max(1, n / 100);
  std::set<int> chosen;
  while (static_cast<int>(chosen.size()) < m) chosen.insert(Pick(rng, n));
  for (int i : chosen) off(i) = Pick(rng, 2) ? 1.0 : -1.0;
  *detail = fmt::format("{} single outliers (1 % of the points), random sign", m);
  return off;
}

Eigen::VectorXd LocalDefectOffsets(const testpieces::ProbingPlan& plan, std::mt19937_64& rng, std::string* detail) {
  const int n = static_cast<int>(plan.points.size());
  Eigen::VectorXd off = Eigen::VectorXd::Zero(n);
  struct Kind { const char* name; int lo, hi; double sign; };
  const Kind kinds[] = {{"burr", 2, 3, 1.0}, {"chip", 4, 6, -1.0}, {"dent", 5, 8, -1.0}};
  const Kind& kind = kinds[Pick(rng, 3)];
  // A feature with enough points that the patch stays a small part of it (<= 25 %).
  for (int attempt = 0; attempt < 100; ++attempt) {
    const int seed = Pick(rng, n);
    const auto idx = NearestOnFeature(plan, plan.points[seed].feature, plan.points[seed].point_part_mm);
    // At most a quarter of the feature (a larger patch is a form error, not a local defect).
    const int size = std::min(kind.lo + Pick(rng, kind.hi - kind.lo + 1), static_cast<int>(idx.size()) / 4);
    if (size < 2) continue;
    for (int k = 0; k < size; ++k) off(idx[k]) = kind.sign * (1.0 - 0.3 * k / std::max(1, size - 1));
    *detail = fmt::format("{} of {} hits on {}", kind.name, size, plan.points[seed].feature);
    return off;
  }
  *detail = "no feature large enough for a patch";
  return off;
}

Eigen::VectorXd FixtureBendOffsets(const testpieces::ProbingPlan& plan, std::mt19937_64& rng, std::string* detail) {
  const int n = static_cast<int>(plan.points.size());
  const int axis = Pick(rng, 2);  // 0: bent along X, 1: along Y
  double lo = 1e300, hi = -1e300;
  for (const auto& p : plan.points) lo = std::min(lo, p.point_part_mm(axis)), hi = std::max(hi, p.point_part_mm(axis));
  const double mid = 0.5 * (lo + hi), half = std::max(1.0, 0.5 * (hi - lo));
  Eigen::VectorXd w(n);  // the bow's Z displacement, then its normal component
  for (int i = 0; i < n; ++i) {
    const double u = (plan.points[i].point_part_mm(axis) - mid) / half;
    w(i) = u * u;
  }
  w.array() -= w.mean();
  Eigen::VectorXd off(n);
  for (int i = 0; i < n; ++i) off(i) = w(i) * plan.points[i].normal_part.z();
  const double peak = off.cwiseAbs().maxCoeff();
  if (peak > 0) off /= peak;
  *detail = fmt::format("part bent along its Z, quadratic in {} over {:.0f} mm", axis ? 'Y' : 'X', hi - lo);
  return off;
}

Eigen::VectorXd SpindleGrowthOffsets(const testpieces::ProbingPlan& plan, std::mt19937_64& rng, std::string* detail) {
  const int n = static_cast<int>(plan.points.size());
  std::map<int, double> growth;
  for (const auto& p : plan.points) growth.emplace(p.cut.axes.op, 0.0);
  for (auto& [op, g] : growth) g = Uniform(rng, -1.0, 1.0);
  Eigen::VectorXd off(n);
  for (int i = 0; i < n; ++i) off(i) = growth[plan.points[i].cut.axes.op] * plan.points[i].normal_part.z();
  const double peak = off.cwiseAbs().maxCoeff();
  if (peak > 0) off /= peak;
  *detail = fmt::format("tool growth along Z stepping with each of {} operations", growth.size());
  return off;
}

}  // namespace tpcal::pipeline
