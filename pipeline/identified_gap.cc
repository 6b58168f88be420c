#include "pipeline/identified_gap.h"

#include <utility>

namespace tpcal::pipeline {

Result<DiagnosisResult> DiagnoseIdentified(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                                           const IdentifyStageResult& stage, const PointSet& measured,
                                           DiagnosisOptions options) {
  options.base_parameters = stage.parameters;
  DiagnosisOptions whole = options;
  options.nominal_slot_design = stage.nominal_slot_design;
  options.prior_outliers = stage.outliers;
  options.prior_local_defects = stage.local_defects;
  auto d = DiagnoseObservations(piece, machine, stage.observations, options);
  if (!d.ok()) return d.status();
  if (d->verdict.family == "local_defect" && stage.unscreened_observations) {
    // The stage's screen left the patches out with no effect in the model: the diagnosis of every
    // point screens again and names the effect whose model leaves no patch, as `tpcal diagnose` does.
    whole.nominal_slot_design = stage.unscreened_slot_design;
    auto again = DiagnoseObservations(piece, machine, *stage.unscreened_observations, whole);
    if (again.ok() && !again->explained_patches.empty()) d = std::move(again);
  }
  AttachSourceLines(measured, &*d);
  return std::move(*d);
}

}  // namespace tpcal::pipeline
