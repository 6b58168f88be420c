// Orientation characteristics (ISO 1101 parallelism, perpendicularity) as signed angles and
// as zone widths. All vectors and points in the datum frame; vectors unit and ORIENTED (their
// sense fixed by the plan's rules, gdt/plan.h FeatureSpec::nominal_direction).
//
// SIGN CONVENTION (written once here, tested in orientation_test.cc and inspection_test.cc):
// the tilt of a feature direction u relative to a datum direction v is split into rotations
// about the two datum-frame axes perpendicular to v's dominant axis k, with the right-hand rule
// of ISO 841 / ISO 230-1 (a = about X, b = about Y, c = about Z):
//     k = Z: (a, b)    k = X: (b, c)    k = Y: (c, a)
// With (i, j, k) the cyclic triple (X, Y, Z), (Y, Z, X) or (Z, X, Y):
//     angle_about_i = atan2(-u_j, u_k) - atan2(-v_j, v_k)
//     angle_about_j = atan2( u_i, u_k) - atan2( v_i, v_k)
// so that u = Rot_i(angle) v and u = Rot_j(angle) v are recovered exactly when v is the datum
// axis k (the usual case: the datum plane defines the frame's Z). For the seed 002 Table 1 #2
// parallelism of B1 to B_R (datum normal +Z):
//     da = angle about +X: positive when the face rises toward +Y (dz/dy = tan(da) > 0),
//     db = angle about +Y: positive when the face falls toward +X (dz/dx = -tan(db) < 0).
// If u . v < 0, u is flipped first (a plane normal and its negative are the same plane).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>

#include "core/status.h"

namespace tpcal::gdt {

struct TiltAngles {
  int axis_i = 0;  // 0 = X, 1 = Y, 2 = Z: the datum axis of the first angle
  int axis_j = 1;  // the datum axis of the second angle
  double about_i_rad = 0;
  double about_j_rad = 0;
  double total_rad = 0;  // angle between u and v, in [0, pi/2]
};

// Index (0, 1, 2) of the component of largest magnitude.
int DominantAxis(const Eigen::Vector3d& v);

// Tilt of direction u relative to datum direction v (both unit), per the convention above.
TiltAngles TiltOf(const Eigen::Vector3d& u, const Eigen::Vector3d& v);

struct ParallelismResult {
  TiltAngles tilt;
  // ISO 1101 zone: distance between the two planes parallel to the datum plane (normal to
  // the datum axis) that enclose `feature_points` (mm). Includes the feature's form.
  double zone_mm = 0;
  // Orientation part only: the same width for the feature's fitted (ideal) geometry over the
  // feature's extent: the LS plane over the extent of its points, or the LS axis over its
  // length. A plane's normal tilted by t over a width w gives about w * tan(t).
  double tilt_zone_mm = 0;
};

// Plane to datum plane: u = feature normal, v = datum normal. `feature_points` are the
// feature's measured points, `feature_point_mm` a point of its LS plane.
ParallelismResult PlaneParallelism(const Eigen::Vector3d& feature_normal, const Eigen::Vector3d& feature_point_mm,
                                   const Eigen::Vector3d& datum_normal, std::span<const Eigen::Vector3d> feature_points);

// Axis (line3, cylinder axis) to datum axis: tilt only; zone_mm is the orientation-only width
// over the feature's extent along its axis (the ISO cylindrical zone of a derived median line
// needs a minimum-circumscribed evaluation not done here), equal to tilt_zone_mm.
ParallelismResult AxisParallelism(const Eigen::Vector3d& feature_direction, const Eigen::Vector3d& datum_direction,
                                  double feature_length_mm);

struct SquarenessResult {
  // Perpendicular pairs (plane to plane, axis to axis): angle_rad = asin(u . v) with the
  // oriented directions: positive when the angle between u and v is LESS than 90 degrees.
  std::optional<double> angle_rad;
  // Mixed pairs (axis to plane, plane to axis: u ideally parallel to v): tilt of u from v per
  // the convention above, zero when perpendicular.
  std::optional<TiltAngles> tilt;
  double zone_mm = 0;       // width of the ISO zone (see EvaluateSquareness)
  bool zone_includes_form = false;  // true when zone_mm is computed from the measured points
};

enum class DirectedKind { kPlaneNormal, kAxis };

// Squareness of a feature (plane normal or axis direction u, with representative points:
// a plane's measured points, a line's measured points, or a cylinder's two axis end points)
// to a datum (plane normal or axis v). Zones, all in the datum frame:
//   plane to plane: planes perpendicular to the datum plane, normal w = u - (u.v)v normalised
//                   (orientation about the datum normal taken from the LS normal, not optimised)
//   axis to axis and plane to axis: planes perpendicular to the datum axis (normal w = v): exact.
//   axis to plane: cylinder parallel to v; diameter taken from the two extreme points of the
//                   feature's points projected on its own axis (orientation only, no form).
// Errors: kDegenerate if a plane-to-plane pair is parallel (no perpendicular direction).
Result<SquarenessResult> EvaluateSquareness(DirectedKind feature_kind, const Eigen::Vector3d& u,
                                            std::span<const Eigen::Vector3d> feature_points,
                                            DirectedKind datum_kind, const Eigen::Vector3d& v);

}  // namespace tpcal::gdt
