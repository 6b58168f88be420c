// Least-squares (orthogonal distance) plane, ISO 10360-6 Gaussian criterion.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>

#include "fitting/features.h"
#include "fitting/fit_result.h"

namespace tpcal::fitting {

// Plane through >= 3 non-collinear points. Normal sign: along `normal_hint` if given, else
// along the mean of nothing: +z component non-negative (then +y, then +x) for determinism.
// covariance parameters: {"offset_mm", "tilt_u_rad", "tilt_v_rad"} at the centroid, (u, v) in-plane.
// Errors: kTooFewPoints (< 3), kDegenerate (collinear or coincident points).
Result<FitResult<Plane>> FitPlane(std::span<const Eigen::Vector3d> points_mm, const FitOptions& options = {},
                                  std::optional<Eigen::Vector3d> normal_hint = std::nullopt);

}  // namespace tpcal::fitting
