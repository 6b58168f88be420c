#include "gdt/datum_frame.h"

#include <cmath>
#include <vector>

#include "fitting/circle_fit.h"

namespace tpcal::gdt {

namespace {
constexpr double kSenseCosMin = 1e-6;   // |cos| below which a sense vector does not decide a sign
constexpr double kParallelSinMin = 1e-9;  // rad: x direction closer than this to z is degenerate
}  // namespace

Result<Eigen::Vector3d> OrientAlong(const Eigen::Vector3d& direction, const Eigen::Vector3d& sense,
                                    const std::string& what) {
  const double s = sense.norm();
  if (!(s > 0.0) || !std::isfinite(s))
    return Status(StatusCode::kDegenerate, what + ": the sense reference is a zero vector");
  const double c = direction.dot(sense) / s;
  if (!(std::abs(c) > kSenseCosMin))
    return Status(StatusCode::kDegenerate, what + ": the sense reference is perpendicular to the axis, cannot orient it");
  return c > 0 ? direction : Eigen::Vector3d(-direction);
}

Result<Rigid3> DatumFromAxes(const Eigen::Vector3d& origin_mm, const Eigen::Vector3d& z_axis,
                             const Eigen::Vector3d& x_direction) {
  const Eigen::Vector3d z = z_axis.normalized();
  const Eigen::Vector3d x_perp = x_direction - z * z.dot(x_direction);
  if (!(x_perp.norm() > kParallelSinMin * x_direction.norm()))
    return Status(StatusCode::kDegenerate, "datum X direction is parallel to the datum Z axis");
  const Eigen::Vector3d x = x_perp.normalized();
  const Eigen::Vector3d y = z.cross(x);
  // cmm_from_datum has the datum axes as columns; invert the isometry.
  Eigen::Matrix3d cmm_r_datum;
  cmm_r_datum.col(0) = x;
  cmm_r_datum.col(1) = y;
  cmm_r_datum.col(2) = z;
  return MakeRigid(cmm_r_datum, origin_mm).inverse();
}

Result<Eigen::Vector3d> ProjectedCircleCenter(std::span<const Eigen::Vector3d> points_mm, const fitting::Plane& plane,
                                              const fitting::FitOptions& options) {
  const Eigen::Vector3d z = plane.normal.normalized();
  const Eigen::Vector3d u = AnyPerpendicular(z);
  const Eigen::Vector3d v = z.cross(u);
  // Centre the in-plane coordinates on the points' centroid for conditioning.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : points_mm) centroid += p;
  if (!points_mm.empty()) centroid /= static_cast<double>(points_mm.size());
  std::vector<Eigen::Vector2d> uv;
  uv.reserve(points_mm.size());
  for (const auto& p : points_mm) uv.emplace_back(u.dot(p - centroid), v.dot(p - centroid));
  auto fit = fitting::FitCircle2(uv, options);
  if (!fit.ok()) return fit.status();
  const Eigen::Vector2d c = fit->feature.center_mm;
  const Eigen::Vector3d center = centroid + u * c.x() + v * c.y();
  return Eigen::Vector3d(center - z * plane.SignedDistance(center));
}

Result<Rigid3> TurningDatumFromCmm(const fitting::Plane& primary, const Eigen::Vector3d& center_mm,
                                   const Eigen::Vector3d& x_target_mm) {
  const Eigen::Vector3d z = primary.normal.normalized();
  const Eigen::Vector3d origin = center_mm - z * primary.SignedDistance(center_mm);
  const Eigen::Vector3d to_target = x_target_mm - origin;
  auto frame = DatumFromAxes(origin, z, to_target);
  if (!frame.ok()) return frame.status().WithContext("turning datum frame: the X target projects onto the origin");
  return frame;
}

Result<Rigid3> ThreeTwoOneDatumFromCmm(const fitting::Plane& primary, const fitting::Line3& secondary,
                                       const Eigen::Vector3d& tertiary_mm) {
  const Eigen::Vector3d z = primary.normal.normalized();
  const Eigen::Vector3d d = secondary.direction - z * z.dot(secondary.direction);
  if (!(d.norm() > kParallelSinMin))
    return Status(StatusCode::kDegenerate, "3-2-1 datum frame: the secondary line is normal to the primary plane");
  const Eigen::Vector3d x = d.normalized();
  const Eigen::Vector3d q = secondary.point_mm - z * primary.SignedDistance(secondary.point_mm);
  const Eigen::Vector3d t = tertiary_mm - z * primary.SignedDistance(tertiary_mm);
  const Eigen::Vector3d origin = q + x * x.dot(t - q);
  return DatumFromAxes(origin, z, x);
}

Result<Rigid3> TargetsDatumFromCmm(const fitting::Plane& primary, const Eigen::Vector3d& center_mm,
                                   const Eigen::Vector3d& target_mm, bool target_sets_y) {
  const Eigen::Vector3d z = primary.normal.normalized();
  const Eigen::Vector3d origin = center_mm - z * primary.SignedDistance(center_mm);
  const Eigen::Vector3d to_target = target_mm - origin;
  // +Y toward the target: +X = Y x Z (right-handed).
  auto frame = DatumFromAxes(origin, z, target_sets_y ? Eigen::Vector3d(to_target.cross(z)) : to_target);
  if (!frame.ok()) return frame.status().WithContext("targets datum frame: the target projects onto the origin");
  return frame;
}

}  // namespace tpcal::gdt
