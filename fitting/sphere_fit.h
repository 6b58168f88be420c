// Least-squares (orthogonal distance) sphere, ISO 10360-6 Gaussian criterion.
#pragma once

#include <Eigen/Core>
#include <span>

#include "fitting/features.h"
#include "fitting/fit_result.h"

namespace tpcal::fitting {

// covariance parameters: {"center_x_mm", "center_y_mm", "center_z_mm", "radius_mm"}.
// Errors: kTooFewPoints (< 4), kDegenerate (coplanar points).
Result<FitResult<Sphere>> FitSphere(std::span<const Eigen::Vector3d> points_mm, const FitOptions& options = {});

}  // namespace tpcal::fitting
