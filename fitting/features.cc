#include "fitting/features.h"

#include <Eigen/Geometry>
#include <cmath>
#include <ostream>
#include <sstream>
#include <string>

#include "core/units.h"

namespace tpcal::fitting {
namespace {

bool AllFinite(const Eigen::Vector3d& v) { return v.allFinite(); }

Result<Eigen::Vector3d> UnitDirection(const Eigen::Vector3d& d, const char* what) {
  const double n = d.norm();
  if (!AllFinite(d) || !(n > 0.0)) {
    std::ostringstream os;
    os << what << " must be a finite non-zero vector, got (" << d.transpose() << ")";
    return Status(StatusCode::kInvalidArgument, os.str());
  }
  return Eigen::Vector3d(d / n);
}

Status CheckPoint(const Eigen::Vector3d& p, const char* what) {
  if (AllFinite(p)) return Status::Ok();
  std::ostringstream os;
  os << what << " must be finite, got (" << p.transpose() << ")";
  return Status(StatusCode::kInvalidArgument, os.str());
}

Status CheckRadius(double r_mm) {
  if (std::isfinite(r_mm) && r_mm > 0.0) return Status::Ok();
  return Status(StatusCode::kInvalidArgument, "radius_mm must be finite and > 0, got " + std::to_string(r_mm));
}

// (axial, radial) coordinates of p about an axis through point with unit direction axis.
Eigen::Vector2d AxialRadial(const Eigen::Vector3d& point, const Eigen::Vector3d& axis, const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = p - point;
  const double w = axis.dot(d);
  return {w, (d - w * axis).norm()};
}

void PrintVec(std::ostream& os, const Eigen::Ref<const Eigen::VectorXd>& v) {
  os << '(';
  for (Eigen::Index i = 0; i < v.size(); ++i) os << (i ? ", " : "") << v[i];
  os << ')';
}

}  // namespace

Result<Line3> MakeLine3(const Eigen::Vector3d& point_mm, const Eigen::Vector3d& direction) {
  TPCAL_RETURN_IF_ERROR(CheckPoint(point_mm, "Line3.point_mm"));
  auto d = UnitDirection(direction, "Line3.direction");
  TPCAL_RETURN_IF_ERROR(d);
  return Line3{point_mm, *d};
}

Result<Plane> MakePlane(const Eigen::Vector3d& point_mm, const Eigen::Vector3d& normal) {
  TPCAL_RETURN_IF_ERROR(CheckPoint(point_mm, "Plane.point_mm"));
  auto n = UnitDirection(normal, "Plane.normal");
  TPCAL_RETURN_IF_ERROR(n);
  return Plane{point_mm, *n};
}

Result<Circle3> MakeCircle3(const Eigen::Vector3d& center_mm, const Eigen::Vector3d& axis, double radius_mm) {
  TPCAL_RETURN_IF_ERROR(CheckPoint(center_mm, "Circle3.center_mm"));
  auto a = UnitDirection(axis, "Circle3.axis");
  TPCAL_RETURN_IF_ERROR(a);
  TPCAL_RETURN_IF_ERROR(CheckRadius(radius_mm));
  return Circle3{center_mm, *a, radius_mm};
}

Result<Cylinder> MakeCylinder(const Eigen::Vector3d& point_mm, const Eigen::Vector3d& axis, double radius_mm) {
  TPCAL_RETURN_IF_ERROR(CheckPoint(point_mm, "Cylinder.point_mm"));
  auto a = UnitDirection(axis, "Cylinder.axis");
  TPCAL_RETURN_IF_ERROR(a);
  TPCAL_RETURN_IF_ERROR(CheckRadius(radius_mm));
  return Cylinder{point_mm, *a, radius_mm};
}

Result<Cone> MakeCone(const Eigen::Vector3d& point_mm, const Eigen::Vector3d& axis, double half_angle_rad,
                      double radius_mm) {
  TPCAL_RETURN_IF_ERROR(CheckPoint(point_mm, "Cone.point_mm"));
  auto a = UnitDirection(axis, "Cone.axis");
  TPCAL_RETURN_IF_ERROR(a);
  if (!(std::isfinite(half_angle_rad) && half_angle_rad > 0.0 && half_angle_rad < kPi / 2)) {
    return Status(StatusCode::kInvalidArgument,
                  "Cone.half_angle_rad must be in (0, pi/2), got " + std::to_string(half_angle_rad));
  }
  TPCAL_RETURN_IF_ERROR(CheckRadius(radius_mm));
  return Cone{point_mm, *a, half_angle_rad, radius_mm};
}

double SignedDistance(const Line2& f, const Eigen::Vector2d& p_mm) {
  const Eigen::Vector2d d = p_mm - f.point_mm;
  return f.direction.x() * d.y() - f.direction.y() * d.x();  // direction x d
}

double Distance(const Line2& f, const Eigen::Vector2d& p_mm) { return std::abs(SignedDistance(f, p_mm)); }

double Distance(const Line3& f, const Eigen::Vector3d& p_mm) { return f.direction.cross(p_mm - f.point_mm).norm(); }

double Distance(const Plane& f, const Eigen::Vector3d& p_mm) { return f.SignedDistance(p_mm); }

double Distance(const Circle2& f, const Eigen::Vector2d& p_mm) { return (p_mm - f.center_mm).norm() - f.radius_mm; }

double Distance(const Circle3& f, const Eigen::Vector3d& p_mm) {
  const Eigen::Vector2d wr = AxialRadial(f.center_mm, f.axis, p_mm);
  return std::hypot(wr.x(), wr.y() - f.radius_mm);
}

double Distance(const Sphere& f, const Eigen::Vector3d& p_mm) { return (p_mm - f.center_mm).norm() - f.radius_mm; }

double Distance(const Cylinder& f, const Eigen::Vector3d& p_mm) {
  return AxialRadial(f.point_mm, f.axis, p_mm).y() - f.radius_mm;
}

double Distance(const Cone& f, const Eigen::Vector3d& p_mm) {
  // In the half-plane (w axial, rho radial) the nappe is the ray from the apex
  // (w_apex, 0) along (cos a, sin a); a = half angle.
  const Eigen::Vector2d wr = AxialRadial(f.point_mm, f.axis, p_mm);
  const double c = std::cos(f.half_angle_rad), s = std::sin(f.half_angle_rad);
  const double w_apex = -f.radius_mm / std::tan(f.half_angle_rad);
  const double along = (wr.x() - w_apex) * c + wr.y() * s;
  if (along < 0.0) return std::hypot(wr.x() - w_apex, wr.y());  // nearest point is the apex
  return (wr.y() - f.radius_mm) * c - wr.x() * s;
}

bool SameDirection(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double tol_rad) {
  const double angle = std::atan2(a.cross(b).norm(), std::abs(a.dot(b)));
  return angle <= tol_rad;  // false for NaN input
}

std::ostream& operator<<(std::ostream& os, const Line2& f) {
  os << "Line2{point_mm=";
  PrintVec(os, f.point_mm);
  os << ", direction=";
  PrintVec(os, f.direction);
  return os << '}';
}

std::ostream& operator<<(std::ostream& os, const Line3& f) {
  os << "Line3{point_mm=";
  PrintVec(os, f.point_mm);
  os << ", direction=";
  PrintVec(os, f.direction);
  return os << '}';
}

std::ostream& operator<<(std::ostream& os, const Plane& f) {
  os << "Plane{point_mm=";
  PrintVec(os, f.point_mm);
  os << ", normal=";
  PrintVec(os, f.normal);
  return os << '}';
}

std::ostream& operator<<(std::ostream& os, const Circle2& f) {
  os << "Circle2{center_mm=";
  PrintVec(os, f.center_mm);
  return os << ", radius_mm=" << f.radius_mm << '}';
}

std::ostream& operator<<(std::ostream& os, const Circle3& f) {
  os << "Circle3{center_mm=";
  PrintVec(os, f.center_mm);
  os << ", axis=";
  PrintVec(os, f.axis);
  return os << ", radius_mm=" << f.radius_mm << '}';
}

std::ostream& operator<<(std::ostream& os, const Sphere& f) {
  os << "Sphere{center_mm=";
  PrintVec(os, f.center_mm);
  return os << ", radius_mm=" << f.radius_mm << '}';
}

std::ostream& operator<<(std::ostream& os, const Cylinder& f) {
  os << "Cylinder{point_mm=";
  PrintVec(os, f.point_mm);
  os << ", axis=";
  PrintVec(os, f.axis);
  return os << ", radius_mm=" << f.radius_mm << '}';
}

std::ostream& operator<<(std::ostream& os, const Cone& f) {
  os << "Cone{point_mm=";
  PrintVec(os, f.point_mm);
  os << ", axis=";
  PrintVec(os, f.axis);
  return os << ", half_angle_rad=" << f.half_angle_rad << ", radius_mm=" << f.radius_mm << '}';
}

}  // namespace tpcal::fitting
