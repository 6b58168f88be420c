// Least-squares (orthogonal distance) sphere, ISO 10360-6 Gaussian criterion.
#pragma once

#include <Eigen/Core>
#include <span>

#include "fitting/features.h"
#include "fitting/fit_result.h"

namespace tpcal::fitting {

// Same method as FitCircle2 in three dimensions (Hyper-type algebraic start on centred,
// scaled data, then Levenberg-Marquardt). Works on caps down to 20 deg half angle.
// covariance parameters: {"center_x_mm", "center_y_mm", "center_z_mm", "radius_mm"}.
// Residuals: |p - c| - R.
// Errors: kTooFewPoints (< 4), kDegenerate (coincident or coplanar points, or a radius beyond
// 1e6 x the RMS distance of the points from their centroid), kNotConverged, kInvalidArgument.
Result<FitResult<Sphere>> FitSphere(std::span<const Eigen::Vector3d> points_mm, const FitOptions& options = {});

}  // namespace tpcal::fitting
