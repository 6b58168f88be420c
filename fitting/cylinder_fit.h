// Least-squares (orthogonal distance) cylinder and cone, ISO 10360-6 Gaussian criterion.
// Start from `axis_hint` if given (e.g. the nominal axis), else from an algebraic/eigen
// analysis of the data; refine by Levenberg-Marquardt in a local axis parametrisation.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>

#include "fitting/features.h"
#include "fitting/fit_result.h"

namespace tpcal::fitting {

// covariance parameters: {"offset_u_mm", "offset_v_mm", "tilt_u_rad", "tilt_v_rad", "radius_mm"}
// in a frame (u, v) normal to the fitted axis at Cylinder::point_mm.
// Axis sign: along axis_hint if given, else positive dot with the data's spread direction.
// Errors: kTooFewPoints (< 5), kDegenerate (points do not span a cylinder), kNotConverged.
Result<FitResult<Cylinder>> FitCylinder(std::span<const Eigen::Vector3d> points_mm, const FitOptions& options = {},
                                        std::optional<Eigen::Vector3d> axis_hint = std::nullopt);

// covariance parameters: {"offset_u_mm", "offset_v_mm", "tilt_u_rad", "tilt_v_rad",
// "radius_mm", "half_angle_rad"}. Errors: kTooFewPoints (< 6), kDegenerate, kNotConverged.
Result<FitResult<Cone>> FitCone(std::span<const Eigen::Vector3d> points_mm, const FitOptions& options = {},
                                std::optional<Eigen::Vector3d> axis_hint = std::nullopt);

}  // namespace tpcal::fitting
