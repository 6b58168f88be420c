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
  kMaxIterations,  // stopped at max_iterations close to a minimum (last step < 1e-6 relative);
                   // result is the best found, message says how far. Farther away the fit
                   // returns kNotConverged instead of a result.
};
const char* TerminationName(Termination t);

struct FitOptions {
  int max_iterations = 100;          // Gauss-Newton / LM iterations
  double step_tolerance_mm = 1e-13;  // converged when every parameter step is below this (relative
                                     // to the feature size for lengths; rad for angles)
  bool compute_covariance = true;    // fill FitResult::covariance
  bool keep_residuals = true;        // fill FitResult::residuals_mm
  bool keep_jacobian = false;        // fill FitResult::jacobian (n x p doubles: memory!)
  // kInvalidArgument unless max_iterations >= 1 and 0 < step_tolerance_mm <= 1e-3.
  Status Validate() const;
};

// Residual statistics of signed orthogonal distances (mm): positive away from the axis/centre
// for circles, spheres, cylinders and cones (outside a shaft, into the material of a hole),
// along +normal for planes, to the left of the direction for 2D lines; unsigned for 3D lines.
// Circle3: the radial deviation in the fitted plane (what roundness uses).
struct ResidualStats {
  double rms_mm = 0;   // sqrt(mean r^2)
  double min_mm = 0;
  double max_mm = 0;
  double form_mm = 0;  // max - min: the form deviation about the LS feature (not minimum zone)
  double sigma_mm = 0; // sqrt(sum r^2 / (n - dof)): the residual standard deviation
                       // (0 when n == dof: no redundancy)
};

// The result of fitting feature type F to n points.
// covariance: sigma^2 (J^T J)^-1 in the minimal parametrisation named by parameter_names
// (units in the names, e.g. "center_x_mm", "tilt_x_rad"), expressed in a local frame
// documented per fit function; `local_axes` holds that frame's axes.
template <typename F>
struct FitResult {
  F feature;
  ResidualStats stats;
  std::size_t n_points = 0;
  std::vector<double> residuals_mm;          // per input point, same order (if keep_residuals)
  Eigen::MatrixXd covariance;                // p x p (if compute_covariance; empty when n == p)
  std::vector<std::string> parameter_names;  // size p
  // Columns (u, v, w) of the local frame named in parameter_names, in input coordinates:
  // w is the normal / axis / line direction, (u, v) span the plane normal to it. Identity
  // for fits whose parameters are global (Circle2, Sphere); 2D fits use the top-left 2x2.
  Eigen::Matrix3d local_axes = Eigen::Matrix3d::Identity();
  // d residual_i / d parameter_j (mm per unit of parameter j) at the result, n x p, rows in
  // input order (if keep_jacobian; not for Line3, whose residual is a 2D vector). Input to
  // fitting/leave_one_out.h.
  Eigen::MatrixXd jacobian;
  Termination termination = Termination::kClosedForm;
  int iterations = 0;
  std::string message;
};

}  // namespace tpcal::fitting
