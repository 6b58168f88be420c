// Least-squares (orthogonal distance) cylinder and cone, ISO 10360-6 Gaussian criterion.
// Start from `axis_hint` if given (e.g. the nominal axis), else from an exhaustive search of
// axis directions scored by the algebraic residual of the best surface about each (moments
// up to order four of a sample, ~2000 directions plus the principal axes; robust on 20 deg
// arcs, where the principal axes mislead: see fitting/internal/axis_fit.h); the three best
// distinct directions are refined by Levenberg-Marquardt in a local axis parametrisation on
// a sample of at most 16384 points, the best on all points.
// point_mm: the foot of the data centroid on the axis.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>

#include "fitting/features.h"
#include "fitting/fit_result.h"

namespace tpcal::fitting {

// covariance parameters: {"offset_u_mm", "offset_v_mm", "tilt_u_rad", "tilt_v_rad", "radius_mm"}
// in the frame local_axes = (u, v, axis) at Cylinder::point_mm (tilts rotate the axis toward
// u and v about that point). Residuals: distance to the axis minus radius.
// Axis sign: along axis_hint if given, else +z component positive (then +y, then +x).
// Errors: kTooFewPoints (< 5), kDegenerate (coincident, collinear or coplanar points, a
// single ring (axis tilt undetermined), radius beyond 1e6 x the RMS distance of the points
// from their centroid),
// kNotConverged, kInvalidArgument (non-finite point or hint, bad options).
Result<FitResult<Cylinder>> FitCylinder(std::span<const Eigen::Vector3d> points_mm, const FitOptions& options = {},
                                        std::optional<Eigen::Vector3d> axis_hint = std::nullopt);

// covariance parameters: {"offset_u_mm", "offset_v_mm", "tilt_u_rad", "tilt_v_rad",
// "radius_mm", "half_angle_rad"}, frame as FitCylinder; radius_mm is the radius at
// Cone::point_mm. Residuals: (rho - R) cos(a) - w sin(a), the distance to the nappe.
// Axis sign: toward the wider end (axis_hint only seeds the direction).
// Errors: kTooFewPoints (< 6), kDegenerate (as FitCylinder; half angle 0 (a cylinder: use
// FitCylinder) or 90 deg (a plane); points on both sides of the apex), kNotConverged.
Result<FitResult<Cone>> FitCone(std::span<const Eigen::Vector3d> points_mm, const FitOptions& options = {},
                                std::optional<Eigen::Vector3d> axis_hint = std::nullopt);

}  // namespace tpcal::fitting
