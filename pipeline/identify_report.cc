#include "pipeline/identify_report.h"

#include <fmt/format.h>

#include <optional>
#include <utility>

#include "pipeline/axis_profiles.h"
#include "pipeline/identified_gap.h"
#include "pipeline/piece_loader.h"
#include "pipeline/seed002_items.h"

namespace tpcal::pipeline {
namespace {

// Turning piece: the closed-form solution (kinematics equations) from the GD&T items, when the
// piece's geometry and every item are there.
void AddClosedForm(const testpieces::TestPiece& piece, const gdt::InspectionResult& inspection,
                   IdentificationReport* r) {
  if (piece.kind() != testpieces::PieceKind::kTurning) return;
  auto geometry = Seed002GeometryOf(piece);
  auto items = Seed002ItemsFromInspection(inspection);
  if (!geometry.ok() || !items.ok()) return;
  r->items = *items;
  auto cf = kinematics::SolveSeed002(*items, *geometry, kinematics::Seed002Equations::kKinematics);
  if (cf.ok()) r->closed_form = std::move(*cf);
}

}  // namespace

Result<IdentificationReport> BuildIdentificationReport(const testpieces::TestPiece& piece,
                                                       const kinematics::MachineModel& machine,
                                                       const PointSet& measured,
                                                       const IdentifyStageOptions& options, bool gap_check) {
  auto stage = RunIdentifyStage(piece, machine, measured, options);
  if (!stage.ok()) return stage.status();
  std::optional<GapCheck> check;
  if (gap_check) {
    DiagnosisOptions gap_options;
    gap_options.screen_outliers = options.screen_outliers;
    auto d = DiagnoseIdentified(piece, machine, *stage, measured, gap_options);
    if (d.ok()) check = GapCheckOf(*d);
  }
  auto motions = CAxisErrorMotions(piece, *stage);
  if (!motions.ok()) return motions.status();
  auto straight = LinearAxisStraightness(piece, *stage);
  if (!straight.ok()) return straight.status();
  IdentificationReport r(std::move(stage->identification));
  r.testpiece = piece.name;
  r.machine = kinematics::MachineTypeName(machine.type);
  r.points_source = stage->inspection.points_source;
  r.outliers = stage->outliers;
  r.local_defects = stage->local_defects;
  r.neighbour_sigma_um = stage->neighbour_sigma_um;
  r.gap_check = std::move(check);
  AddClosedForm(piece, stage->inspection, &r);
  r.error_motion = std::move(*motions);
  r.straightness = std::move(*straight);
  return r;
}

Result<IdentificationReport> IdentifyPointFile(const IdentifyRequest& request) {
  auto setup = LoadPiece({.testpiece = request.testpiece, .config_path = request.config_path,
                          .machine_path = request.machine_path, .wording = {.name_piece_errors = true}});
  if (!setup.ok()) return setup.status();
  auto columns = ParsePointColumns(request.columns);
  if (!columns.ok()) return columns.status();
  PointReadOptions read;
  read.columns = std::move(*columns);
  auto points = ReadLabelledPoints(request.points_path, setup->piece, request.labelling, read);
  if (!points.ok()) return points.status();
  auto info = [&](const std::string& line) {
    if (request.info) request.info(line);
  };
  if (points->raw_scan) info("raw scan labelled: " + points->raw_scan->BriefReport());
  IdentifyStageOptions options;
  options.parameters = request.parameters;
  options.screen_outliers = !request.keep_outliers;
  options.identify = IdentifyOptionsFor(request.uncertainty, request.mc_trials, request.subset_trials, request.seed);
  info(fmt::format("tpcal identify: {} points of the {} from {}", points->points.size(), setup->piece.name,
                   request.points_path));
  auto report = BuildIdentificationReport(setup->piece, setup->machine, points->points, options, request.gap_check);
  if (!report.ok()) return report.status();
  if (request.gap_check && !report->gap_check) info("gap check: the diagnosis could not be run on these points");
  if (report->gap_check && !report->gap_check->warning.empty()) info("WARNING: " + report->gap_check->warning);
  return report;
}

}  // namespace tpcal::pipeline
