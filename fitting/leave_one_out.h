// Closed-form leave-one-out for a converged least-squares fit, for jackknife and
// cross-validation work without n refits.
//
// With residuals r (model minus data, the fitters' convention) and Jacobian J = dr/dtheta
// (n x p) at the minimum (J^T r = 0), deleting observation i moves the solution by
//   delta_theta_(i) = (J^T J)^-1 j_i r_i / (1 - h_ii),   h_ii = j_i^T (J^T J)^-1 j_i
// (Sherman-Morrison on the normal equations; exact for linear least squares, first order in
// the residuals for the nonlinear fitters), and the deleted point's residual about that fit
// is the PRESS residual r_i / (1 - h_ii). Computed from a QR factorisation of J, O(n p^2).
// Use with FitOptions::keep_jacobian = true: FitResult::jacobian and residuals_mm.
#pragma once

#include <Eigen/Core>
#include <span>

#include "core/status.h"

namespace tpcal::fitting {

struct LeaveOneOut {
  Eigen::MatrixXd delta;            // n x p: parameter change when observation i is left out
  Eigen::VectorXd leverage;         // h_ii in [0, 1], sum = p
  Eigen::VectorXd press_residuals;  // r_i / (1 - h_ii), units of r
};

// Errors: kInvalidArgument (sizes differ, non-finite input), kTooFewPoints (n <= p),
// kDegenerate (J rank-deficient), kNotIdentifiable (an observation with leverage 1 within
// 1e-12: without it the parameters are not determined; the message names it).
Result<LeaveOneOut> ComputeLeaveOneOut(const Eigen::MatrixXd& jacobian, std::span<const double> residuals);

// Jackknife covariance of the parameters from the leave-one-out deltas:
// (n - 1) / n * sum_i (delta_i - mean)(delta_i - mean)^T.
Eigen::MatrixXd JackknifeCovariance(const LeaveOneOut& loo);

}  // namespace tpcal::fitting
