#include "pipeline/identified_gap.h"

#include <utility>

namespace tpcal::pipeline {

Result<DiagnosisResult> DiagnoseIdentified(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                                           const IdentifyStageResult& stage, const PointSet& measured,
                                           DiagnosisOptions options) {
  options.base_parameters = stage.parameters;
  options.nominal_slot_design = stage.nominal_slot_design;
  options.prior_outliers = stage.outliers;
  options.prior_local_defects = stage.local_defects;
  auto d = DiagnoseObservations(piece, machine, stage.observations, options);
  if (!d.ok()) return d.status();
  AttachScreenLines(measured, &d->outliers, &d->local_defects);
  return std::move(*d);
}

}  // namespace tpcal::pipeline
