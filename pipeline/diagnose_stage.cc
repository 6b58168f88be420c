#include "pipeline/diagnose_stage.h"

#include <fmt/format.h>

#include <filesystem>
#include <optional>
#include <utility>

#include "core/ascii.h"
#include "kinematics/errors_yaml.h"
#include "pipeline/identified_gap.h"
#include "pipeline/identify_stage.h"
#include "pipeline/instrument_reference.h"
#include "pipeline/io/point_io.h"
#include "pipeline/scan_cells.h"

namespace tpcal::pipeline {
namespace {

// The reference file by its extension: machine errors into options->reference, or a point file
// into *points.
Status LoadDiagnosisReference(const std::string& path, const kinematics::MachineModel& machine,
                              DiagnosisOptions* options, std::optional<PointSet>* points) {
  const std::string ext = AsciiLower(std::filesystem::path(path).extension().string());
  options->reference_name = std::filesystem::path(path).filename().string();
  if (ext == ".yaml" || ext == ".yml") {
    auto ref = kinematics::LoadErrorState(path, machine);
    if (!ref.ok()) return ref.status();
    options->reference = std::move(*ref);
    options->reference_path = path;
  } else if (PointFormatFromExtension(path) != PointFormat::kAuto) {
    auto ref = ReadPoints(path);
    if (!ref.ok()) return ref.status();
    *points = std::move(*ref);
  } else {
    return Status(StatusCode::kInvalidArgument,
                  "--reference " + path +
                      ": expected machine errors (.yaml, .yml) or a point file (.csv, .ply, .pcd, .xyz, .txt)");
  }
  return Status::Ok();
}

std::string ReferenceKind(const DiagnoseRequest& r, bool reference_points) {
  if (r.reference_path.empty()) return "";
  if (!r.reference_instrument.empty()) return r.reference_instrument;
  if (IsIdentificationReference(r.reference_path)) return "identification";
  return reference_points ? "points" : "machine errors";
}

std::map<std::string, std::string> DiagnosisInputs(const DiagnoseRequest& r, bool reference_points) {
  std::map<std::string, std::string> inputs{{"points", r.points_path},
          {"testpiece", r.config_path.empty() ? r.testpiece : r.config_path},
          {"machine", r.machine_path.empty() ? "nominal" : r.machine_path},
          {"reference", r.reference_path},
          {"reference_kind", ReferenceKind(r, reference_points)},
          {"noise_um", fmt::format("{}", r.noise_um)},
          {"alpha", fmt::format("{}", r.alpha)},
          {"keep_outliers", r.keep_outliers ? "true" : "false"}};
  if (!r.reference_setup.empty()) inputs["reference_setup"] = r.reference_setup;
  if (r.reference_probe_radius_mm) inputs["reference_probe_radius_mm"] = fmt::format("{}", *r.reference_probe_radius_mm);
  return inputs;
}

// Above this many points (and without a point reference) a file is diagnosed as `tpcal run` does:
// identified, re-aligned and re-associated in the corrected frame (pooled into cells above
// ScanCellOptions::above_points). Diagnose fits the re-alignment of the GD&T datum frame
// linearly, which misses t^2 / 2R on shifted holes; more points make it visible. Clean turning
// pieces with random Table 2 errors (10-50 um / urad), 1 um noise, not `none` through Diagnose /
// through the stage: 2 / 2 of 12 at 2 112 points (the same two verdicts), 1 / 0 of 12 at 4 224,
// 3 / 0 of 8 at 7 920, 5 / 0 of 8 at 15 840, 4 / 0 of 4 at 63 360 (probe_radius, or harmonic 2 on
// the holes unexplained). The plans (16 points per circle, 8 per hole) stay on the validated path.
constexpr std::size_t kReAlignedAbovePoints = 3000;

// The file through RunIdentifyStage (analytic u) and DiagnoseIdentified. Point by point in the
// GD&T frame a 2e6-point scan also took 64 s and 9.9 GB. Sets *cells to "N points in M
// scan-line cells" (or "... cells of a fixed grid ...") when pooled.
Result<DiagnosisResult> DiagnoseReAligned(const LoadedPiece& setup, const PointSet& points,
                                          const DiagnosisOptions& options, std::string* cells) {
  IdentifyStageOptions stage_options;
  stage_options.identify = IdentifyOptionsFor("analytic", 0, 0, 1);
  stage_options.screen_outliers = options.screen_outliers;
  auto stage = RunIdentifyStage(setup.piece, setup.machine, points, stage_options);
  if (!stage.ok()) return stage.status();
  if (stage->scan_cells)
    *cells = fmt::format("{} points in {} {}", stage->scan_cells->num_points, stage->scan_cells->num_cells,
                         stage->scan_cells->on_grid ? "cells of a fixed grid (the file is not in scan order)"
                                                    : "scan-line cells");
  return DiagnoseIdentified(setup.piece, setup.machine, *stage, points, options);
}

}  // namespace

Result<LoadedPiece> LoadDiagnosisPiece(const DiagnoseRequest& r) {
  return LoadPiece({.testpiece = r.testpiece, .config_path = r.config_path, .machine_path = r.machine_path,
                    .config_must_match_name = r.testpiece_given,
                    .wording = {.unknown_name_prefix = "--testpiece: ", .unknown_name_suffix = " (or --config FILE)"}});
}

Result<DiagnoseStageResult> RunDiagnoseStage(const LoadedPiece& setup, const DiagnoseRequest& r) {
  auto columns = ParsePointColumns(r.columns);
  if (!columns.ok()) return columns.status();
  PointReadOptions read;
  read.columns = std::move(*columns);
  auto points = ReadLabelledPoints(r.points_path, setup.piece, r.labelling, read);
  if (!points.ok()) return points.status();
  if (points->raw_scan && r.info) r.info("raw scan labelled: " + points->raw_scan->BriefReport());
  DiagnosisOptions options;
  options.noise_um = r.noise_um;
  options.alpha = r.alpha;
  options.screen_outliers = !r.keep_outliers;
  if (!r.reference_setup.empty() && r.reference_instrument.empty())
    return Status(StatusCode::kInvalidArgument, "--reference-setup needs --reference-instrument probe_artifacts or ballbar");
  if (r.reference_probe_radius_mm && r.reference_instrument != "probe_artifacts")
    return Status(StatusCode::kInvalidArgument, "--reference-probe-radius-mm needs --reference-instrument probe_artifacts");
  if (!r.reference_instrument.empty() || IsIdentificationReference(r.reference_path)) {
    if (r.reference_path.empty())
      return Status(StatusCode::kInvalidArgument, "--reference-instrument needs --reference FILE (the instrument's file)");
    auto d = DiagnoseAgainstInstrument(setup, points->points,
                                       {.path = r.reference_path,
                                        .instrument = r.reference_instrument,
                                        .setup_path = r.reference_setup,
                                        .machine_path = r.machine_path,
                                        .probe_radius_mm = r.reference_probe_radius_mm},
                                       options);
    if (!d.ok()) return d.status();
    return DiagnoseStageResult{std::move(*d), DiagnosisInputs(r, false)};
  }
  std::optional<PointSet> reference_points;
  if (!r.reference_path.empty()) {
    if (Status s = LoadDiagnosisReference(r.reference_path, setup.machine, &options, &reference_points); !s.ok())
      return s;
  }
  if (r.info)
    r.info(fmt::format("tpcal diagnose: {} points of the {} from {}", points->points.size(), setup.piece.name,
                       r.points_path));
  std::string cells;
  const bool re_aligned = !reference_points && points->points.size() > kReAlignedAbovePoints;
  auto result = reference_points ? DiagnoseAgainstPoints(setup.piece, setup.machine, points->points, *reference_points, options)
                : re_aligned     ? DiagnoseReAligned(setup, points->points, options, &cells)
                                 : Diagnose(setup.piece, setup.machine, points->points, options);
  if (!result.ok()) return result.status();
  DiagnoseStageResult out{std::move(*result), DiagnosisInputs(r, reference_points.has_value())};
  if (!cells.empty()) {
    out.inputs["scan_cells"] = cells;
    if (r.info) r.info("dense scan: " + cells + " (re-aligned and pooled as tpcal run does)");
  } else if (re_aligned && r.info) {
    r.info(fmt::format("more than {} points: identified, re-aligned and re-associated as tpcal run does",
                       kReAlignedAbovePoints));
  }
  return out;
}

Result<std::string> RunValidationStage(const LoadedPiece& setup, const ValidationOptions& v) {
  auto summary = RunValidation(setup.piece, setup.machine, v);
  if (!summary.ok()) return summary.status();
  return ValidationStageMarkdown(setup, v, *summary);
}

std::string ValidationStageMarkdown(const LoadedPiece& setup, const ValidationOptions& v, const ValidationSummary& summary) {
  return fmt::format("Diagnosis validation{}: {} piece, seed {}, trials {}, magnitudes {} ({} peak), noise {} um\n\n",
                     v.reference_name.empty() ? "" : " against a " + v.reference_name, setup.piece.name, v.seed,
                     v.trials, fmt::join(v.magnitudes, ","), v.scale_raw_peak ? "raw signature" : "visible signature",
                     fmt::join(v.noise_um, ",")) +
         ValidationMarkdown(summary);
}

}  // namespace tpcal::pipeline
