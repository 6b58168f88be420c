// Least-squares (orthogonal distance) lines, ISO 10360-6 Gaussian criterion.
#pragma once

#include <Eigen/Core>
#include <span>

#include "fitting/features.h"
#include "fitting/fit_result.h"

namespace tpcal::fitting {

// 2D line through >= 2 distinct points. Direction sign: positive dot with (last - first point).
// covariance parameters: {"offset_mm", "angle_rad"} about the centroid.
// Errors: kTooFewPoints (< 2), kDegenerate (all points coincide).
Result<FitResult<Line2>> FitLine2(std::span<const Eigen::Vector2d> points_mm, const FitOptions& options = {});

// 3D line through >= 2 distinct points; same sign rule. covariance parameters:
// {"offset_u_mm", "offset_v_mm", "tilt_u_rad", "tilt_v_rad"} in a frame (u, v) normal to the line.
Result<FitResult<Line3>> FitLine3(std::span<const Eigen::Vector3d> points_mm, const FitOptions& options = {});

}  // namespace tpcal::fitting
