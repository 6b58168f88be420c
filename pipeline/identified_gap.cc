#include "pipeline/identified_gap.h"

#include <utility>

namespace tpcal::pipeline {

Result<DiagnosisResult> DiagnoseIdentified(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                                           const IdentifyStageResult& stage, const PointSet& measured,
                                           DiagnosisOptions options) {
  options.base_parameters = stage.parameters;
  const bool left_out = stage.unscreened_observations.has_value();
  options.nominal_slot_design = left_out ? stage.unscreened_slot_design : stage.nominal_slot_design;
  auto d = DiagnoseObservations(piece, machine, left_out ? *stage.unscreened_observations : stage.observations, options);
  if (!d.ok()) return d.status();
  AttachSourceLines(measured, &*d);
  return std::move(*d);
}

}  // namespace tpcal::pipeline
