// Datum-ball test (seed 001; touch probe or R-test on a ball fixed to the rotary table): at each
// rotary command the machine's linear commands that centre the probe on the ball are read. Under
// machine errors those commands move away from the nominal ones; their change over the rotary
// positions identifies the location errors of the rotary axes and the squareness of the linear
// axes (seed 001: 11 position-independent errors of a B/C table, kinematics::IsoLocationSet).
//
// Model. The ball centre b (part frame, mm: fixed to the last rotary axis) and the tool point
// (contact_in_tool = 0: the probe-ball or R-test centre) coincide:
//   ToolPointInPart(errors, {X, Y, Z, rotary}, 0) = b,
// solved for the linear commands (X, Y, Z) by Newton (BallCentreCommand). The reading is those
// commands (mm). Identification: least squares over the readings (3 residuals each, um) of the
// active coefficients and, unless given, the ball centre b (a nuisance, as on a real machine),
// Gauss-Newton with exact Jacobians: d(XYZ)/d(theta) = -A^-1 dP/d(theta), A = dP/d(XYZ),
// dP/db = -I (P = tool point in part). Identifiability, estimable combinations and the analytic
// uncertainty as kinematics::Identify does (identification.h: columns in display units, the
// nuisance projected out, rank tolerance 1e-3); jackknife over readings (delete one reading,
// linearised at the solution).
//
// Weights. When every reading has u_um > 0 (the standard uncertainty of each of its three
// coordinates), the residuals are divided by it (weighted least squares, rows whitened); sigma is
// then the chi-like scale sqrt(sum (r / u)^2 / dof) (about 1 when the u_um are right) and the
// analytic covariance is scale^2 (J^T W J)^-1.
//
// Monte Carlo (monte_carlo_runs > 0): readings re-simulated as the model at the solution plus
// Gaussian noise (sd: the fitted sigma, or each reading's u_um when weighted, with no scale) are
// re-identified by the least-squares map linearised at the solution (one Gauss-Newton step from
// it: the centring commands are linear in the errors to well below 1e-3 um over micrometre noise,
// see datum_ball_test.cc); u = the standard deviation of the re-identified values, 95 % interval
// from their quantiles (MonteCarloUncertainty). Draws: std::mt19937_64(monte_carlo_seed),
// StandardNormal (core/portable_random.h), reading by reading, x, y, z.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/status.h"
#include "kinematics/axis_state.h"
#include "kinematics/error_state.h"
#include "kinematics/identification.h"
#include "kinematics/machine_model.h"

namespace tpcal::kinematics {

struct BallReading {
  AxisState rotary;                 // rotary commands (and t_s); the linear members are ignored
  Eigen::Vector3d command_mm = Eigen::Vector3d::Zero();  // measured X, Y, Z centring the probe
  std::size_t line = 0;             // source line (0: none)
  double u_um = 0.0;                // standard uncertainty of each coordinate, um (0: not given)
};

// The linear commands (mm) that put the tool point on `ball_part_mm` at `rotary` under `errors`.
// Errors: kNotConverged when Newton does not reach 1e-9 mm in 20 steps.
Result<Eigen::Vector3d> BallCentreCommand(const MachineModel& model, const ErrorState& errors,
                                          const AxisState& rotary, const Eigen::Vector3d& ball_part_mm);

struct DatumBallOptions {
  std::vector<std::string> parameters;            // empty: IsoLocationSet(model)
  std::optional<Eigen::Vector3d> ball_part_mm;    // known ball centre; unset: fitted (nuisance)
  double rank_tolerance = 1e-3;                   // as IdentifyOptions::rank_tolerance
  int max_iterations = 10;
  bool jackknife = true;                          // delete-one-reading jackknife beside analytic
  int monte_carlo_runs = 200;                     // Monte Carlo re-identifications; 0 = off, else >= 2
  std::uint64_t monte_carlo_seed = 1;             // std::mt19937_64 seed of the Monte Carlo noise
};

struct DatumBallResult {
  explicit DatumBallResult(ErrorState base) : fitted(std::move(base)) {}
  // Primary: analytic; uncertainties: analytic, jackknife_points (if on), monte_carlo (if on).
  std::vector<ParameterEstimate> parameters;
  // Their analytic covariance (display units, k = 1, `parameters`' order): rank-deficient along
  // the combinations the readings do not determine (zero there).
  Eigen::MatrixXd covariance;
  Identifiability identifiability;
  ErrorState fitted;
  Eigen::Vector3d ball_part_mm = Eigen::Vector3d::Zero();  // fitted (or given)
  Eigen::Vector3d ball_u_um = Eigen::Vector3d::Zero();     // analytic, k = 1 (0 when given)
  std::vector<Eigen::Vector3d> residuals_um;  // per reading: measured - model command
  double rms_before_um = 0.0, rms_after_um = 0.0;  // of the residuals, um (unweighted)
  double sigma_um = 0.0;     // sqrt(SSR / dof) of the unweighted residuals, um
  bool weighted = false;     // the readings' u_um were used as weights
  double chi_scale = 0.0;    // weighted: sqrt(sum (r / u)^2 / dof), the scale of the analytic u; else 0
  int monte_carlo_runs = 0;  // done (0: off)
  int iterations = 0;
};

// Errors: kInvalidArgument (a parameter unknown to the machine, a machine without rotary axes,
// options, u_um < 0 or not finite, or given for some readings and not others: the line named), kTooFewPoints (3 x readings <= parameters + nuisance), kNotIdentifiable (nothing
// identifiable), kNotConverged (a reading the model cannot centre, its line named).
Result<DatumBallResult> IdentifyDatumBall(const MachineModel& model, std::span<const BallReading> readings,
                                          const DatumBallOptions& options = {});

}  // namespace tpcal::kinematics
