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
  Eigen::MatrixXd columns_um;    // n x k: the directions fitted, each scaled by its standard deviation
  Eigen::MatrixXd remaining_um;  // n x r: K off `columns_um` = remaining_um remaining_um^T
};

// With K = P J S J^T P (J: d deviation (um) / d coefficient of `uncertainty.names` at
// `reference`, display units; S their covariance; P the projection off `held_design`, one row per
// observation: the base's fitted columns and the re-alignment), the eigenvectors of K with
// eigenvalue above ratio * uncertainty.noise_um^2, scaled by the root of their eigenvalue, at most
// n / 2 - held_design.cols() of them (the largest; the noise stays estimable), and the others
// scaled alike. Errors: unknown names, a covariance of the wrong size or not finite, noise_um <=
// 0, held_design rows != observations, those of the linearisation.
Result<ReferenceNuisance> ReferenceNuisanceColumns(const kinematics::MachineModel& machine,
                                                   const kinematics::ErrorState& reference,
                                                   std::span<const kinematics::Observation> observations,
                                                   const Eigen::MatrixXd& held_design,
                                                   const ReferenceUncertainty& uncertainty, double ratio);

}  // namespace tpcal::pipeline::diagnosis_internal
