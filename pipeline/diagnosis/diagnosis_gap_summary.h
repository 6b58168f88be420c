// Step 4 of the diagnosis (diagnosis.h): where the gap lies. Statistics of the gap per feature,
// operation and A (or B) index with their excess over noise, its linear trend with machining
// time, and the harmonics of every circular profile. Internal to the diagnosis library.
#pragma once

#include <Eigen/Core>

#include "kinematics/machine_model.h"
#include "pipeline/diagnosis/diagnosis.h"
#include "testpieces/point_association.h"

namespace tpcal::pipeline::diagnosis_internal {

// The gap `gap_um` (per observation) summarised against the noise sigma `sigma_um` into out's
// by_feature, by_operation, by_a_index, drift, harmonics and standing_out (groups first, then
// harmonics). With a reference's own uncertainty (its leftover factor off the fitted columns,
// BaseFit::reference_remaining_um: n x r, um; no column: none), every test weighs the variance
// it adds, mean and spread (SatterthwaiteLaw), and the drift's u holds its share.
// Observations of unequal noise (pooled scan cells, Observation::noise_scale s_i): sigma_um is one
// hit's, the tests weigh r_i / s_i (and the factor's rows / s_i), the statistics (RMS, mean, maximum,
// amplitude, phase, drift) are of the gap itself, and the drift's u holds each s_i.
void SummariseGap(const kinematics::MachineModel& machine, const testpieces::MeasuredObservations& observations,
                  const Eigen::VectorXd& gap_um, double sigma_um, const DiagnosisOptions& options,
                  DiagnosisResult* out, const Eigen::MatrixXd& reference_remaining_um = Eigen::MatrixXd());

}  // namespace tpcal::pipeline::diagnosis_internal
