#include "pipeline/identified_gap.h"

#include <utility>

namespace tpcal::pipeline {

Result<DiagnosisResult> DiagnoseIdentified(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                                           const IdentifyStageResult& stage, const PointSet& measured,
                                           DiagnosisOptions options) {
  options.base_parameters = stage.parameters;
  const bool left_out = stage.unscreened_observations.has_value();
  options.nominal_slot_design = left_out ? stage.unscreened_slot_design : stage.nominal_slot_design;
  options.neighbour_graph = stage.neighbour_graph;
  auto d = DiagnoseObservations(piece, machine, left_out ? *stage.unscreened_observations : stage.observations, options);
  if (!d.ok()) return d.status();
  AttachSourceLines(measured, &*d);
  // A dense scan's hits flagged inside their cells head the list.
  d->outliers.insert(d->outliers.begin(), stage.flagged_hits.begin(), stage.flagged_hits.end());
  return std::move(*d);
}

}  // namespace tpcal::pipeline
