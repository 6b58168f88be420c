// Step 0 of the diagnosis (diagnosis.h): the outlier screen (outlier_screen.h) on the base model
// fitted to every point, and the input of the other steps without the flagged points. Internal
// to the diagnosis library.
#pragma once

#include <Eigen/Core>
#include <optional>

#include "pipeline/diagnosis/diagnosis.h"
#include "pipeline/diagnosis/diagnosis_base_fit.h"
#include "pipeline/diagnosis/outlier_screen.h"
#include "testpieces/point_association.h"

namespace tpcal::pipeline::diagnosis_internal {

struct ScreenedInput {
  OutlierScreen screen;
  bool left_out = false;                                // some points are left out: the fields below hold the rest
  testpieces::MeasuredObservations observations;        // the kept observations
  Eigen::VectorXd reference_dev_um;                     // their point-reference deviations (if any)
  DiagnosisOptions options;                             // nominal_slot_design: its kept rows, or none
};

// The screen of `fit` (the base fitted to every observation of `mo`); with options.screen_outliers
// off it is still run and reported, nothing is left out.
// `effect` (n x p, or null): columns of an effect the model holds besides the base (the
// verdict's candidate on every observation, with the pair's second when the verdict names both),
// so that points it explains are not flagged.
ScreenedInput ScreenBaseFit(const BaseFit& fit, const testpieces::MeasuredObservations& mo,
                            const DiagnosisOptions& options, const Eigen::VectorXd* reference_dev_um,
                            const Eigen::MatrixXd* effect = nullptr);

// Lists the flagged points and patches in `out` (lines are attached later: AttachScreenLines).
void ReportScreen(const ScreenedInput& in, const testpieces::MeasuredObservations& mo, DiagnosisResult* out);

}  // namespace tpcal::pipeline::diagnosis_internal
