// Geometric features as small value types. Lengths in mm, angles in rad, directions unit
// vectors. Invariants (unit direction, positive radius) are enforced by the Make* factories,
// which return an error for invalid input; the fitters only ever produce valid features.
// Direction sign: a line/axis/normal direction d and -d describe the same feature; fitters
// choose the sign documented at each fit function (compare with SameDirection).
#pragma once

#include <Eigen/Core>
#include <iosfwd>
#include <string>

#include "core/status.h"

namespace tpcal::fitting {

struct Line2 {
  Eigen::Vector2d point_mm;   // a point on the line (fitters: the centroid's foot)
  Eigen::Vector2d direction;  // unit
};

struct Line3 {
  Eigen::Vector3d point_mm;   // a point on the line (fitters: the centroid's foot)
  Eigen::Vector3d direction;  // unit
};

struct Plane {
  Eigen::Vector3d point_mm;  // a point on the plane (fitters: the centroid's foot)
  Eigen::Vector3d normal;    // unit
  // Signed distance of p from the plane, along normal (mm).
  double SignedDistance(const Eigen::Vector3d& p_mm) const { return normal.dot(p_mm - point_mm); }
};

struct Circle2 {
  Eigen::Vector2d center_mm;
  double radius_mm;  // > 0
};

// A circle in space: centre, unit axis normal to its plane, radius.
struct Circle3 {
  Eigen::Vector3d center_mm;
  Eigen::Vector3d axis;  // unit
  double radius_mm;      // > 0
};

struct Sphere {
  Eigen::Vector3d center_mm;
  double radius_mm;  // > 0
};

struct Cylinder {
  Eigen::Vector3d point_mm;  // a point on the axis (fitters: foot of the data centroid)
  Eigen::Vector3d axis;      // unit
  double radius_mm;          // > 0
};

// Right circular cone: the section through point_mm normal to axis is a circle of radius
// radius_mm; the radius grows by tan(half_angle_rad) per mm along +axis.
// half_angle_rad in (0, pi/2). The apex lies at point_mm - axis * radius_mm / tan(half_angle).
struct Cone {
  Eigen::Vector3d point_mm;  // a point on the axis (fitters: foot of the data centroid)
  Eigen::Vector3d axis;      // unit, pointing toward the wider end
  double half_angle_rad;
  double radius_mm;          // radius at point_mm, > 0
};

// Factories that check the invariants (normalise directions; reject zero vectors and
// non-positive radii/angles out of range with kInvalidArgument).
Result<Line3> MakeLine3(const Eigen::Vector3d& point_mm, const Eigen::Vector3d& direction);
Result<Plane> MakePlane(const Eigen::Vector3d& point_mm, const Eigen::Vector3d& normal);
Result<Circle3> MakeCircle3(const Eigen::Vector3d& center_mm, const Eigen::Vector3d& axis, double radius_mm);
Result<Cylinder> MakeCylinder(const Eigen::Vector3d& point_mm, const Eigen::Vector3d& axis, double radius_mm);
Result<Cone> MakeCone(const Eigen::Vector3d& point_mm, const Eigen::Vector3d& axis,
                      double half_angle_rad, double radius_mm);

// Signed orthogonal distance of a point to each feature's surface (mm); positive outside
// (away from the axis/centre; along +normal for planes). Lines: unsigned distance.
double Distance(const Line2& f, const Eigen::Vector2d& p_mm);
double Distance(const Line3& f, const Eigen::Vector3d& p_mm);
double Distance(const Plane& f, const Eigen::Vector3d& p_mm);
double Distance(const Circle2& f, const Eigen::Vector2d& p_mm);
double Distance(const Circle3& f, const Eigen::Vector3d& p_mm);  // to the circle curve, unsigned
double Distance(const Sphere& f, const Eigen::Vector3d& p_mm);
double Distance(const Cylinder& f, const Eigen::Vector3d& p_mm);
double Distance(const Cone& f, const Eigen::Vector3d& p_mm);  // to the nappe on the apex's +axis side;
                                                              // behind the apex: distance to the apex
// Signed distance of p from a 2D line: positive to the left of `direction` (along the
// direction rotated by +90 deg). FitLine2's residuals use this sign.
double SignedDistance(const Line2& f, const Eigen::Vector2d& p_mm);

// True if unit vectors a and b are parallel or antiparallel within tol_rad.
bool SameDirection(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double tol_rad);

// Printable with named fields and units, e.g. "Circle2{center_mm=(1, 2), radius_mm=3}".
std::ostream& operator<<(std::ostream& os, const Line2& f);
std::ostream& operator<<(std::ostream& os, const Line3& f);
std::ostream& operator<<(std::ostream& os, const Plane& f);
std::ostream& operator<<(std::ostream& os, const Circle2& f);
std::ostream& operator<<(std::ostream& os, const Circle3& f);
std::ostream& operator<<(std::ostream& os, const Sphere& f);
std::ostream& operator<<(std::ostream& os, const Cylinder& f);
std::ostream& operator<<(std::ostream& os, const Cone& f);

}  // namespace tpcal::fitting
