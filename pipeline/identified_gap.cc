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
  // A dense scan's hits flagged inside their cells (the stage's first outliers) head the list.
  if (stage.scan_cells && stage.scan_cells->flagged_hits > 0) {
    const auto hits = stage.outliers.begin() + static_cast<std::ptrdiff_t>(stage.scan_cells->flagged_hits);
    d->outliers.insert(d->outliers.begin(), stage.outliers.begin(), hits);
  }
  return std::move(*d);
}

}  // namespace tpcal::pipeline
