// What result.json (run_json.h) and report.html (report_html.h) of `tpcal run` show, handed
// over by the stage layer (pipeline/run_output.h, ReportOf). The results are pointed to, not
// copied: the run's RunResult must outlive the view. The settings and the input's summaries are
// copies of a few values each.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/frames.h"
#include "gdt/inspection.h"
#include "kinematics/identification.h"
#include "pipeline/diagnosis/diagnosis.h"
#include "pipeline/report/svg_figures.h"

namespace tpcal::pipeline {

// The effective tpcal.pipeline/1 settings that result.json's "config" lists.
struct RunSettings {
  std::string testpiece;
  std::string points;
  std::string machine;  // "" = the nominal machine of the piece kind
  std::vector<std::string> parameters;
  std::uint64_t seed = 1;
  kinematics::UncertaintyMethod primary = kinematics::UncertaintyMethod::kJackknifePoints;
  bool jackknife_groups = true;
  int monte_carlo_trials = 0;
  bool diagnose = true;
  std::string truth;  // "" = none
  FigureOptions figures;
  std::string reference_instrument;  // "" = no reference
  std::string reference_file;
  std::string yaml;  // every setting, defaults included, as config.yaml holds them
};

// The point file as read: format name ("csv", "qif", ...), units it was written in ("mm", "in").
struct RunInputSummary {
  std::string format;
  std::string source_units;
  std::size_t num_points = 0;  // in the file (a raw scan: before labelling)
  std::string digest_xxh64;    // of the file's bytes, 16 hex digits
};

// A file without labels, labelled by the piece (pipeline/raw_scan_labeling.h).
struct RawScanSummary {
  std::size_t num_points = 0;
  std::size_t num_rejected = 0;
  double labelled_fraction = 0.0;
  double rms_distance_um = 0.0;
  int symmetry_order = 1;
  std::string symmetry_resolved_by;
  Rigid3 part_from_cmm = Rigid3::Identity();
  std::vector<std::pair<std::string, std::size_t>> points_per_feature;  // piece order
  std::string message;
};

// A dense scan pooled into scan-line cells (pipeline/scan_cells.h).
struct ScanCellsSummary {
  std::size_t num_points = 0;
  std::size_t num_cells = 0;
  double mean_points_per_cell = 0.0;
  std::size_t max_points_per_cell = 0;
  double max_cell_mm = 0.0;
  double max_cell_deg = 0.0;
  bool on_grid = false;  // grid cells: the file was not in scan order
  std::size_t flagged_hits = 0;  // single hits flagged inside their cells (identification.outliers)
  double hit_sigma_um = 0.0;     // one hit's noise about its cell's fit
};

struct RunReport {
  RunSettings settings;
  std::string piece_name;
  std::string machine_name;
  RunInputSummary input;
  std::optional<RawScanSummary> raw_scan;
  std::optional<ScanCellsSummary> scan_cells;
  const gdt::InspectionResult* inspection = nullptr;               // never null
  const kinematics::IdentificationResult* identification = nullptr;  // never null
  // The points the identification's outlier screen flagged (left out of it unless kept); never null.
  const std::vector<ScreenedPoint>* identification_outliers = nullptr;
  const std::vector<LocalDefect>* identification_local_defects = nullptr;
  const DiagnosisResult* diagnosis = nullptr;  // null: none made (diagnosis_error says why when asked)
  std::string diagnosis_error;
  const std::map<std::string, double>* truth = nullptr;  // never null; empty without a stated truth
  const std::vector<Figure>* figures = nullptr;           // never null
};

}  // namespace tpcal::pipeline
