// Least-squares (orthogonal distance) plane, ISO 10360-6 Gaussian criterion.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>

#include "fitting/features.h"
#include "fitting/fit_result.h"

namespace tpcal::fitting {

// Plane through >= 3 non-collinear points (closed form: the centroid and the smallest
// eigenvector of the scatter matrix, accumulated with compensated sums in one pass).
// point_mm: the centroid. Normal sign: along `normal_hint` if given (and not perpendicular
// to it), else +z component positive (if 0: +y, then +x) for determinism.
// covariance parameters: {"offset_mm", "tilt_u_rad", "tilt_v_rad"} at the centroid, with
// local_axes = (u, v, normal): u the major principal in-plane direction of the points,
// v = normal x u (the covariance is then diagonal). Residuals: signed, along +normal.
// Errors: kTooFewPoints (< 3), kDegenerate (coincident points, or collinear: in-plane width
// below ~1e-6 of the length), kInvalidArgument (non-finite point or bad options).
Result<FitResult<Plane>> FitPlane(std::span<const Eigen::Vector3d> points_mm, const FitOptions& options = {},
                                  std::optional<Eigen::Vector3d> normal_hint = std::nullopt);

}  // namespace tpcal::fitting
