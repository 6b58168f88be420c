// Least-squares (orthogonal distance) circles in 2D and in 3D, ISO 10360-6 Gaussian criterion.
// Algebraic start (Hyper / Taubin fit on centred data), then Gauss-Newton / Levenberg-Marquardt.
// Works on partial arcs down to 20 degrees.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>

#include "fitting/features.h"
#include "fitting/fit_result.h"

namespace tpcal::fitting {

// covariance parameters: {"center_x_mm", "center_y_mm", "radius_mm"}.
// Errors: kTooFewPoints (< 3), kDegenerate (collinear points, or radius beyond 1e6 x extent).
Result<FitResult<Circle2>> FitCircle2(std::span<const Eigen::Vector2d> points_mm, const FitOptions& options = {});

// Circle in 3D: LS plane first, then the LS circle of the points projected into that plane
// (the two-step method used by CMM software). Axis sign follows FitPlane's normal rule or
// `axis_hint`. covariance parameters: {"center_u_mm", "center_v_mm", "radius_mm"} in the
// fitted plane, (u, v) in-plane axes.
Result<FitResult<Circle3>> FitCircle3(std::span<const Eigen::Vector3d> points_mm, const FitOptions& options = {},
                                      std::optional<Eigen::Vector3d> axis_hint = std::nullopt);

}  // namespace tpcal::fitting
