#include "gdt/orientation.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace tpcal::gdt {
namespace {

// Range (max - min) of p . w over the points.
double RangeAlong(std::span<const Eigen::Vector3d> points, const Eigen::Vector3d& w) {
  if (points.empty()) return 0.0;
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (const auto& p : points) {
    const double s = w.dot(p);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  return hi - lo;
}

}  // namespace

int DominantAxis(const Eigen::Vector3d& v) {
  int k = 0;
  v.cwiseAbs().maxCoeff(&k);
  return k;
}

TiltAngles TiltOf(const Eigen::Vector3d& u_in, const Eigen::Vector3d& v) {
  const Eigen::Vector3d u = u_in.dot(v) < 0 ? Eigen::Vector3d(-u_in) : u_in;
  const int k = DominantAxis(v);
  const int i = (k + 1) % 3;
  const int j = (k + 2) % 3;
  TiltAngles t;
  t.axis_i = i;
  t.axis_j = j;
  t.about_i_rad = std::atan2(-u(j), u(k)) - std::atan2(-v(j), v(k));
  t.about_j_rad = std::atan2(u(i), u(k)) - std::atan2(v(i), v(k));
  // atan2 of the cross/dot pair is accurate for tiny angles (acos is not).
  t.total_rad = std::atan2(u.cross(v).norm(), u.dot(v));
  return t;
}

ParallelismResult PlaneParallelism(const Eigen::Vector3d& feature_normal, const Eigen::Vector3d& feature_point_mm,
                                   const Eigen::Vector3d& datum_normal, std::span<const Eigen::Vector3d> feature_points) {
  ParallelismResult r;
  r.tilt = TiltOf(feature_normal, datum_normal);
  r.zone_mm = RangeAlong(feature_points, datum_normal);
  // Feet of the points on the feature's LS plane, measured along the datum normal.
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (const auto& p : feature_points) {
    const Eigen::Vector3d foot = p - feature_normal * feature_normal.dot(p - feature_point_mm);
    const double s = datum_normal.dot(foot);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  r.tilt_zone_mm = feature_points.empty() ? 0.0 : hi - lo;
  return r;
}

ParallelismResult AxisParallelism(const Eigen::Vector3d& feature_direction, const Eigen::Vector3d& datum_direction,
                                  double feature_length_mm) {
  ParallelismResult r;
  r.tilt = TiltOf(feature_direction, datum_direction);
  r.tilt_zone_mm = feature_length_mm * std::sin(r.tilt.total_rad);
  r.zone_mm = r.tilt_zone_mm;
  return r;
}

Result<SquarenessResult> EvaluateSquareness(DirectedKind feature_kind, const Eigen::Vector3d& u,
                                            std::span<const Eigen::Vector3d> feature_points,
                                            DirectedKind datum_kind, const Eigen::Vector3d& v) {
  SquarenessResult r;
  if (feature_kind == datum_kind) {  // ideally u perpendicular to v
    r.angle_rad = std::asin(std::clamp(u.dot(v), -1.0, 1.0));
    if (feature_kind == DirectedKind::kPlaneNormal) {
      const Eigen::Vector3d w = u - v * u.dot(v);
      if (!(w.norm() > 1e-9))
        return Status(StatusCode::kDegenerate, "squareness: the feature plane is parallel to the datum plane");
      r.zone_mm = RangeAlong(feature_points, w.normalized());
    } else {
      r.zone_mm = RangeAlong(feature_points, v);
    }
    r.zone_includes_form = true;
    return r;
  }
  r.tilt = TiltOf(u, v);  // ideally u parallel to v
  if (feature_kind == DirectedKind::kPlaneNormal) {  // plane perpendicular to a datum axis
    r.zone_mm = RangeAlong(feature_points, v);
    r.zone_includes_form = true;
  } else {  // axis perpendicular to a datum plane: extreme points on the axis, projected
    const Eigen::Vector3d uu = u.dot(v) < 0 ? Eigen::Vector3d(-u) : u;
    const double length = RangeAlong(feature_points, uu);
    r.zone_mm = length * std::sin(r.tilt->total_rad);
    r.zone_includes_form = false;
  }
  return r;
}

}  // namespace tpcal::gdt
