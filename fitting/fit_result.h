// Options in, Result out: the common options and result record of every least-squares fit.
// "Least squares" is the Gaussian (L2) orthogonal-distance criterion of ISO 10360-6.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "core/status.h"

namespace tpcal::fitting {

enum class Termination {
  kClosedForm,     // solved directly (line, plane): no iteration needed
  kConverged,      // Gauss-Newton / Levenberg-Marquardt step below tolerance
  kMaxIterations,  // stopped at max_iterations; result is the best found (message says how far)
};
const char* TerminationName(Termination t);

struct FitOptions {
  int max_iterations = 100;          // Gauss-Newton / LM iterations
  double step_tolerance_mm = 1e-13;  // converged when every parameter step is below this (relative
                                     // to the feature size for lengths; rad for angles)
  bool compute_covariance = true;    // fill FitResult::covariance
  bool keep_residuals = true;        // fill FitResult::residuals_mm
  Status Validate() const;
};

// Residual statistics of signed orthogonal distances (mm): positive outside material for
// surfaces of revolution, along +normal for planes; unsigned for 3D lines.
struct ResidualStats {
  double rms_mm = 0;   // sqrt(mean r^2)
  double min_mm = 0;
  double max_mm = 0;
  double form_mm = 0;  // max - min: the form deviation about the LS feature (not minimum zone)
  double sigma_mm = 0; // sqrt(sum r^2 / (n - dof)): the residual standard deviation
};

// The result of fitting feature type F to n points.
// covariance: sigma^2 (J^T J)^-1 in the minimal parametrisation named by parameter_names
// (units in the names, e.g. "center_x_mm", "tilt_x_rad"), expressed in a local frame
// documented per fit function.
template <typename F>
struct FitResult {
  F feature;
  ResidualStats stats;
  std::size_t n_points = 0;
  std::vector<double> residuals_mm;          // per input point, same order (if keep_residuals)
  Eigen::MatrixXd covariance;                // p x p (if compute_covariance)
  std::vector<std::string> parameter_names;  // size p
  Termination termination = Termination::kClosedForm;
  int iterations = 0;
  std::string message;
};

}  // namespace tpcal::fitting
