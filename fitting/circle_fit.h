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

// covariance parameters: {"center_x_mm", "center_y_mm", "radius_mm"}. Residuals: |p - c| - R.
// Errors: kTooFewPoints (< 3), kDegenerate (coincident or collinear points, or a radius beyond
// 1e6 x the extent of the data: the RMS distance of the points from their centroid), kNotConverged (Levenberg-Marquardt far from a minimum after
// max_iterations), kInvalidArgument (non-finite point or bad options).
// Accuracy on ISO 10360-6-style certified data (fitting/reference_data.h), arcs of 20 to 360
// deg, radii 1 to 500 mm, 1000 mm from the origin: better than 1e-8 um (circle_fit_test.cc).
// For nearly straight arcs the residuals carry ~eps x R of rounding (they are differences
// of two lengths of size R), so R is only known to ~eps R / sagitta.
Result<FitResult<Circle2>> FitCircle2(std::span<const Eigen::Vector2d> points_mm, const FitOptions& options = {});

// Circle in 3D: LS plane first (FitPlane), then the LS circle of the points projected into
// that plane (the two-step method used by CMM software). Axis: the plane's normal, with
// FitPlane's sign rule or along `axis_hint`. covariance parameters: {"center_u_mm",
// "center_v_mm", "radius_mm"} in the fitted plane; local_axes = (u, v, axis) as FitPlane's.
// The axis direction's uncertainty is FitPlane's on the same points. Residuals: the radial
// deviation in the fitted plane (what roundness uses); the out-of-plane rms is in `message`.
// Errors: as FitPlane, then as FitCircle2.
Result<FitResult<Circle3>> FitCircle3(std::span<const Eigen::Vector3d> points_mm, const FitOptions& options = {},
                                      std::optional<Eigen::Vector3d> axis_hint = std::nullopt);

}  // namespace tpcal::fitting
