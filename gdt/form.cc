#include "gdt/form.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/units.h"

namespace tpcal::gdt {
namespace {

template <typename F>
double Range(std::size_t n, F&& value_of) {
  if (n == 0) return 0.0;
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (std::size_t i = 0; i < n; ++i) {
    const double s = value_of(i);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  return hi - lo;
}

}  // namespace

std::vector<RadialDeviation> CircularityProfile(std::span<const Eigen::Vector2d> points_mm,
                                                const fitting::Circle2& circle) {
  std::vector<RadialDeviation> out;
  out.reserve(points_mm.size());
  for (std::size_t i = 0; i < points_mm.size(); ++i) {
    const Eigen::Vector2d d = points_mm[i] - circle.center_mm;
    double theta = std::atan2(d.y(), d.x());
    if (theta < 0) theta += 2.0 * kPi;
    if (theta >= 2.0 * kPi) theta = 0.0;  // -0 rounding
    out.push_back({theta, d.norm() - circle.radius_mm, i});
  }
  std::sort(out.begin(), out.end(), [](const RadialDeviation& a, const RadialDeviation& b) {
    return a.theta_rad != b.theta_rad ? a.theta_rad < b.theta_rad : a.index < b.index;
  });
  return out;
}

double ProfileRange(std::span<const RadialDeviation> profile) {
  return Range(profile.size(), [&](std::size_t i) { return profile[i].dr_mm; });
}

double LsFlatness(std::span<const Eigen::Vector3d> points_mm, const fitting::Plane& plane) {
  return Range(points_mm.size(), [&](std::size_t i) { return plane.SignedDistance(points_mm[i]); });
}

double LsStraightness2(std::span<const Eigen::Vector2d> points_mm, const fitting::Line2& line) {
  const Eigen::Vector2d n(-line.direction.y(), line.direction.x());
  return Range(points_mm.size(), [&](std::size_t i) { return n.dot(points_mm[i] - line.point_mm); });
}

double LsStraightness3(std::span<const Eigen::Vector3d> points_mm, const fitting::Line3& line) {
  double max_d = 0.0;
  for (const auto& p : points_mm) {
    const Eigen::Vector3d r = p - line.point_mm;
    max_d = std::max(max_d, (r - line.direction * line.direction.dot(r)).norm());
  }
  return 2.0 * max_d;
}

}  // namespace tpcal::gdt
