// Machine errors known from one measurement (a prior: values with standard uncertainties, e.g. a
// probing test) updated by another (a test piece's observations), each weighed by what it knows.
// Linear Gaussian update at the prior: with the piece's deviations y = measured - predicted at
// the prior, their design J (display units, kinematics::LineariseObservations) and the 6-DOF
// re-alignment projected out (P), noise sigma and the prior's covariance S = diag(u^2):
//   delta = (J^T P J / sigma^2 + S^-1)^-1 J^T P y / sigma^2,  posterior = prior + delta.
// A coefficient the prior does not know (u <= 0 or not finite) is weighed by the piece alone;
// one neither sees (information below 1e-6 of the piece's best-seen coefficient's, and of the
// prior's best-known one's) keeps the prior's value, as does a direction below 1e-9 of the Jacobi-scaled information. With u -> 0 the prior
// is kept, with u -> infinity the result is the piece's own least-squares fit (linearised at the
// prior). UpdateWithinPriorCovariance takes the prior's full covariance instead (correlations
// used; S^-1 its pseudo-inverse: a singular S knows only the combinations it spans).
#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

#include "core/status.h"
#include "kinematics/error_state.h"
#include "kinematics/identification.h"
#include "kinematics/machine_model.h"

namespace tpcal::kinematics {

struct PriorUpdate {
  explicit PriorUpdate(ErrorState e) : posterior(std::move(e)) {}
  ErrorState posterior;              // the prior with `delta` added to the active coefficients
  std::vector<double> delta;         // per active coefficient, display units (um, urad)
  std::vector<double> posterior_u;   // per active coefficient, display units, k = 1
};

// `prior_u` holds one standard uncertainty per coefficient of `active` (display units).
// Errors: kInvalidArgument (sizes differ, sigma_um <= 0, no observation), those of
// LineariseObservations.
Result<PriorUpdate> UpdateWithinPrior(const MachineModel& model, const ErrorState& prior, const ActiveSet& active,
                                      std::span<const double> prior_u, std::span<const Observation> observations,
                                      double sigma_um);

// As UpdateWithinPrior with the prior's covariance `prior_cov` (display units, active order; zero
// or rank-deficient along what the prior does not determine). Errors: kInvalidArgument (its size
// is not the active set's, not finite, not symmetric or not positive semi-definite), those of
// UpdateWithinPrior.
Result<PriorUpdate> UpdateWithinPriorCovariance(const MachineModel& model, const ErrorState& prior,
                                                const ActiveSet& active, const Eigen::MatrixXd& prior_cov,
                                                std::span<const Observation> observations, double sigma_um);

}  // namespace tpcal::kinematics
