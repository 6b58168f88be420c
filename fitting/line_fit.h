// Least-squares (orthogonal distance) lines, ISO 10360-6 Gaussian criterion.
#pragma once

#include <Eigen/Core>
#include <span>

#include "fitting/features.h"
#include "fitting/fit_result.h"

namespace tpcal::fitting {

// 2D line through >= 2 distinct points (closed form: centroid and major scatter
// eigenvector). point_mm: the centroid. Direction sign: positive dot with (last - first
// point); if perpendicular, +x then +y. Residuals: SignedDistance (left of the direction
// positive). covariance parameters: {"offset_mm", "angle_rad"} about the centroid, offset
// along the left normal (local_axes.col(0)), angle counter-clockwise; diagonal.
// Errors: kTooFewPoints (< 2), kDegenerate (all points coincide, or no dominant direction:
// scatter eigenvalues within 1e-12 of each other), kInvalidArgument (non-finite point).
Result<FitResult<Line2>> FitLine2(std::span<const Eigen::Vector2d> points_mm, const FitOptions& options = {});

// 3D line through >= 2 distinct points; same method and sign rule (if perpendicular, +z,
// then +y, then +x). Residuals: unsigned distances, so stats.form_mm is not straightness;
// stats.sigma_mm is per residual component, sqrt(sum d^2 / (2n - 4)). covariance
// parameters: {"offset_u_mm", "offset_v_mm", "tilt_u_rad", "tilt_v_rad"} at the centroid in
// the frame local_axes = (u, v, direction), u the second principal direction; diagonal.
// No jacobian (the residual is a 2D vector). Errors: as FitLine2.
Result<FitResult<Line3>> FitLine3(std::span<const Eigen::Vector3d> points_mm, const FitOptions& options = {});

}  // namespace tpcal::fitting
