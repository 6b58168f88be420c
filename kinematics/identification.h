// Identification: machine error coefficients from measured surface points of a machined test
// piece (the point-level solver (b) of the inversion; the GD&T-level closed form of seed 002 is
// kinematics/seed002_closed_form.h).
//
// Model. Each observation is one measured point of a machined surface, already expressed in the
// nominal part frame (via the datum frame), with the machine state that cut it (CutPoint). Its
// normal deviation is predicted by the exact virtual machining of kinematics/simulate.h:
//   r_i(theta, xi) = n0_i . (R(w) m_i + t - p0_i) - s_i(theta)
// theta = the active error coefficients (internal units, mm / rad), xi = (w, t) a small rigid
// re-alignment of the measured points (the datum frame is built from measured features, so it
// carries their errors: a nuisance, always estimated unless disabled). Least squares over all
// points, solved by Ceres (Levenberg-Marquardt) with Jacobians ds/dtheta from automatic
// differentiation through the kinematic chain (SurfaceDeviationJacobian).
//
// Identifiability. The Jacobian, columns scaled to display units (um, urad) and with the nuisance
// projected out, is decomposed by SVD. Directions whose singular value is below
// rank_tolerance * largest (of the projected ones, or the largest column norm before the
// projection when that is larger) are not identifiable: coefficients with a component in them get no
// value (identifiable = false) and the estimable combinations of those coefficients are reported
// by name ("dy_AR(-90) + dz_AR(-90)"), with value and uncertainty. The solution is the
// minimum-norm one in display units (non-identifiable directions set to zero).
// The default tolerance, 1e-3, is practical rather than numerical: a direction 1000 times less
// sensitive than the best-determined one has its uncertainty amplified 1000 times (0.5 um of CMM
// noise then gives u of hundreds of um or urad), so it is reported as not identifiable instead of
// as a number no one should use. Measured: the seed 002 turning plan's weakest direction is 0.029
// of its strongest, M1's 0.36; the cone frustum's default plan has two directions at 7e-5 and 6e-5
// (E_B0A, E_B0C, E_B(0X)Z came out as 700 +- 6000 urad under a 1e-7 tolerance).
//
// Uncertainty (k = 1, display units):
//  - analytic: Gauss-Newton covariance sigma^2 (A^T A)^-1, sigma^2 = SSR / (n - q);
//  - jackknife, delete one point: closed-form leave-one-out updates of the linearised solution
//    (no refit): theta_(i) = theta - (A^T A)^-1 a_i e_i / (1 - h_ii);
//    u^2 = (n - 1) / n * sum (theta_(i) - mean)^2;
//  - jackknife, delete one group (feature): block downdate (A^T A - A_g^T A_g)^-1 A_g^T e_g
//    (Woodbury: no n_g x n_g matrix); a group whose removal makes the system singular leaves the
//    coefficients without a group value;
//  - Monte Carlo (GUM Supplement 1): the linearised least-squares map applied to draws of the
//    point deviations from a scaled-shifted t distribution (nu = n - q) about the fitted values,
//    drawn in parameter space (the image of n normal deviations is normal with covariance
//    (A^T A)^-1), so a trial costs O(m^2), not O(n);
//    u = standard deviation, 95 % interval from the 2.5 / 97.5 % quantiles;
//  - random subsets (seed 002 section 5, optional): k random points per feature, refitted
//    (linearised), standard deviation over trials.
// 95 % intervals of the other methods: value -+ t(0.975, nu) u.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/frames.h"
#include "core/status.h"
#include "kinematics/error_state.h"
#include "kinematics/jacobians.h"
#include "kinematics/machine_model.h"
#include "kinematics/simulate.h"

namespace tpcal::kinematics {

// One measured surface point.
struct Observation {
  CutPoint cut;                                           // how and where it was cut (nominal p0, n0)
  Eigen::Vector3d measured_mm = Eigen::Vector3d::Zero();  // measured point, nominal part frame
  int group = 0;                                          // feature index (delete-one-group jackknife)
  // Noise sigma of this observation's deviation relative to one probe hit's: 1 for a hit, below 1
  // for a pooled scan cell (pipeline/scan_cells.h). Identify weighs it (weighted least squares),
  // as do the diagnosis's noise tests; the diagnosis's fits do not.
  double noise_scale = 1.0;
};

struct LinearDesign;

enum class UncertaintyMethod { kAnalytic, kJackknifePoints, kJackknifeGroups, kMonteCarlo, kRandomSubsets };
const char* UncertaintyMethodName(UncertaintyMethod m);  // "analytic", "jackknife_points", ...

struct IdentifyOptions {
  bool fit_alignment = true;       // estimate the 6-DOF re-alignment nuisance
  int max_iterations = 20;         // Levenberg-Marquardt iterations (2-3 are typical)
  double rank_tolerance = 1e-3;    // relative singular value below which a direction is not identifiable
  // The method whose u fills ParameterEstimate::u and ci95 (the others are reported beside it).
  UncertaintyMethod primary = UncertaintyMethod::kJackknifePoints;
  bool jackknife_groups = true;    // also the delete-one-group jackknife
  int monte_carlo_trials = 0;      // GUM S1 trials; 0 = off
  // Seed 002 section 5, for comparison: keep `random_subset_size` random points of every feature,
  // solve the linearised problem on them, repeat; u = standard deviation of the solutions
  // (trials whose subset cannot determine every coefficient are skipped). 0 = off. It overstates
  // u when points are well spread (each subset fit nearly interpolates its points).
  int random_subset_trials = 0;
  int random_subset_size = 3;
  std::uint64_t seed = 1;          // Monte Carlo and random-subset generator seed
  // The linearisation of the same observations at `base` when the caller already has it (the
  // pipeline derives it from the slot design it shares with the diagnosis): what
  // LineariseObservations(model, base, active, observations) returns. Saves one Jacobian pass;
  // kInvalidArgument if its size does not match.
  std::shared_ptr<const LinearDesign> initial_design;
  Status Validate() const;
};

// An uncertainty of one coefficient by one method (display units).
struct Uncertainty {
  UncertaintyMethod method = UncertaintyMethod::kAnalytic;
  bool available = false;  // false: the method could not give a value (message says why)
  double u = 0.0;          // k = 1
  double ci95_low = 0.0, ci95_high = 0.0;
  std::string message;
};

// `u` (k = 1) by method `m` with its 95 % interval value -+ t(0.975, nu) u; available when u is finite.
Uncertainty MakeUncertainty(UncertaintyMethod m, double value, double u, double nu);

// Monte Carlo (GUM S1) from `draws`, the re-identified values minus `value` (display units): u =
// their standard deviation, 95 % interval value + their 2.5 / 97.5 % quantiles; not available
// (message) with fewer than 2 draws.
Uncertainty MonteCarloUncertainty(double value, std::vector<double> draws);

struct ParameterEstimate {
  std::string name;        // coefficient name (ErrorState), e.g. "dx_CR(0)", "E_XC@A=0.cos2"
  std::string iso_symbol;  // ISO 230-1 symbol or relation (catalog), "" if none
  std::string unit;        // display unit: "um", "urad", ...
  bool identifiable = false;
  double value = 0.0;      // display units; meaningful only if identifiable
  double u = 0.0;          // primary method, k = 1
  double ci95_low = 0.0, ci95_high = 0.0;
  std::vector<Uncertainty> uncertainties;  // every method computed
};

// An estimable combination of non-identifiable coefficients: sum_k coefficients[k] * value[k]
// (display units), normalised so the largest |coefficient| is 1.
struct Combination {
  std::vector<std::string> names;
  std::vector<double> coefficients;
  std::string text;        // "dy_AR(-90) + dz_AR(-90)"
  double value = 0.0;      // display units of the first name
  double u = 0.0;          // analytic, k = 1
};

struct Identifiability {
  int num_parameters = 0;
  int rank = 0;
  double condition_number = 0.0;            // of the identifiable part (scaled, nuisance removed)
  std::vector<double> singular_values;      // scaled, descending
  std::vector<std::string> not_identifiable;
  std::vector<Combination> estimable;       // combinations that the data do determine
  // Directions the data cannot see, as combinations (null space), for the report.
  std::vector<Combination> null_directions;
};

struct IdentificationResult {
  explicit IdentificationResult(ErrorState base) : fitted(std::move(base)) {}
  std::vector<ParameterEstimate> parameters;  // in ActiveSet order
  Identifiability identifiability;
  ErrorState fitted;                 // base errors with the identified coefficients set
  Rigid3 alignment = Rigid3::Identity();  // part_from_measured re-alignment (nuisance)
  std::size_t num_observations = 0;
  int num_groups = 0;
  double rms_before_um = 0.0;        // residual RMS at theta = base, no re-alignment
  double rms_after_um = 0.0;         // at the solution
  double sigma_um = 0.0;             // sqrt(SSR / (n - q)), residuals over noise_scale: one hit's
  int iterations = 0;
  std::string termination;           // Ceres termination summary
  // Passes over all observations that evaluated the Jacobian (the costly part): the
  // linearisation at the base errors, the Ceres evaluations it did not serve, and the
  // linearisation at the solution unless Ceres's own last evaluation was at that very point.
  int jacobian_passes = 0;
  std::vector<double> residuals_um;  // per observation, at the solution (not weighted)
};

// Identifies the coefficients `active` of `base` (all other coefficients stay as in `base`), by
// least squares weighted by 1 / Observation::noise_scale (ordinary when every scale is 1); every
// uncertainty is of that weighted problem. Errors: kTooFewPoints (n <= q), kInvalidArgument
// (options, empty active set, a noise_scale not positive and finite), kNotIdentifiable (no
// coefficient identifiable), simulation failures naming the observation.
Result<IdentificationResult> Identify(const MachineModel& model, const ErrorState& base,
                                      const ActiveSet& active, std::span<const Observation> observations,
                                      const IdentifyOptions& options = {});

// The linearised design of the problem at `errors` (display-unit columns for `active`, then the
// six nuisance columns if fit_alignment): rows = observations. Exposed for diagnosis and tests.
struct LinearDesign {
  Eigen::MatrixXd J_dev_params;      // n x q: d predicted deviation (um) / d coefficient (display units)
  Eigen::MatrixXd J_dev_alignment;   // n x 6: d measured deviation (um) / d (w rad, t mm) ... in um
  Eigen::VectorXd measured_dev_um;   // n0 . (m - p0), um
  Eigen::VectorXd predicted_dev_um;  // s_i(errors), um
};
Result<LinearDesign> LineariseObservations(const MachineModel& model, const ErrorState& errors,
                                           const ActiveSet& active, std::span<const Observation> observations);
// The same design per error slot (jacobians.h): J_dev_params column k = d predicted deviation (um)
// / d slot k (mm or rad, internal units). Errors: a slot on an axis the machine lacks
// (kInvalidArgument), those of LineariseObservations.
Result<LinearDesign> LineariseSlotObservations(const MachineModel& model, const ErrorState& errors,
                                               std::span<const ErrorSlot> slots,
                                               std::span<const Observation> observations);

}  // namespace tpcal::kinematics
