// The reference's own uncertainty in the diagnosis's base model (DiagnosisOptions::
// reference_uncertainty): the directions of the piece's deviations along which the reference's
// covariance moves them by more than a share of the noise variance, fitted as nuisance columns
// so that no candidate is credited with what the reference does not know. Internal to the
// diagnosis library.
#pragma once

#include <Eigen/Core>
#include <span>

#include "core/status.h"
#include "kinematics/error_state.h"
#include "kinematics/identification.h"
#include "kinematics/machine_model.h"
#include "pipeline/diagnosis/diagnosis.h"

namespace tpcal::pipeline::diagnosis_internal {

struct ReferenceNuisance {
  Eigen::MatrixXd columns;    // n x k, um
  Eigen::MatrixXd remaining;  // n x r, um: K off `columns` = remaining remaining^T (the smaller eigenvectors)
};

// With K = P J S J^T P (J: d deviation (um) / d coefficient of `uncertainty.names` at
// `reference`, display units; S their covariance; P the projection off `held_design`'s columns,
// the base's fitted columns and the re-alignment), the eigenvectors of K with eigenvalue above
// ratio * uncertainty.noise_um^2, scaled by the square root of the eigenvalue (um), k >= 0, and
// the others, scaled alike: what K keeps off them. Errors: unknown names, a covariance of the wrong size or
// not finite, noise_um <= 0, those of the linearisation.
Result<ReferenceNuisance> ReferenceNuisanceColumns(const kinematics::MachineModel& machine,
                                                 const kinematics::ErrorState& reference,
                                                 std::span<const kinematics::Observation> observations,
                                                 const Eigen::MatrixXd& held_design,
                                                 const ReferenceUncertainty& uncertainty, double ratio);

}  // namespace tpcal::pipeline::diagnosis_internal
