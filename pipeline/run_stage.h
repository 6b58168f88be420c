// The whole pipeline of `tpcal run` for one point file: read the points, fit the features and
// evaluate the piece's GD&T (datum frame from the measured features), associate every point with
// the cut that made it, identify the machine errors with their uncertainties and identifiability,
// diagnose the sim-to-real gap (pipeline/diagnosis/diagnosis.h: where, which unmodelled effect, how much
// the gap shrinks), then build the figures. The identification is RunIdentifyStage
// (identify_stage.h), the stage of `tpcal identify`; each step is timed and reported as progress.
// No file is written here (run_output.h writes).
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/status.h"
#include "pipeline/diagnosis/diagnosis.h"
#include "pipeline/identify_stage.h"
#include "pipeline/io/point_io.h"
#include "pipeline/raw_scan_labeling.h"
#include "pipeline/run_config.h"
#include "pipeline/report/svg_figures.h"

namespace tpcal::pipeline {

struct StageTiming {
  std::string stage;  // "setup", "read", "label" (raw scans only), "gdt", "associate", "identify", "diagnose",
                      // "figures"
  double seconds = 0.0;
};

// Called when a stage starts (`stage` as in StageTiming) and once with "done".
using ProgressFn = std::function<void(std::string_view stage)>;

struct RunResult {
  PipelineConfig config;         // effective (parameters filled in with the default set)
  std::string piece_name;
  std::string machine_name;
  gdt::InspectionPlan plan;      // the piece's inspection plan
  PointFileInfo points_info;
  std::size_t num_points = 0;    // points in the file (a raw scan: before labelling)
  // Set when the file was a raw scan: placement, per-feature counts, rejected points, RMS, symmetry.
  // (RawScanLabeling::labelled is moved into the stage; only the summary is kept here.)
  std::optional<RawScanLabeling> raw_scan;
  std::string points_digest;     // XXH64 of the point file's bytes, 16 hex digits
  // Set when the scan was pooled into scan-line cells (config.scan_cells): the stage's
  // observations, the identification and the diagnosis are then per cell.
  std::optional<ScanCellSummary> scan_cells;
  IdentifyStageResult stage;     // inspection, observations, parameters, identification
  // Gap diagnosis with the identified parameter set as the base model (config.diagnose), or, when
  // config names a reference instrument, against that instrument (instrument_reference.h: the
  // piece identified again with the instrument's parameters unless they are the run's, or for
  // error maps with the run's identification; reference_agreement set); when it could not be
  // made (e.g. no residual degrees of freedom) diagnosis_status says why and the rest of the run
  // stands.
  std::optional<DiagnosisResult> diagnosis;
  Status diagnosis_status;
  std::map<std::string, double> truth;  // stated truth (display units) when config.truth is set
  std::vector<Figure> figures;
  std::vector<StageTiming> timings;
};

struct RunOptions {
  int read_threads = 0;  // point parser threads (0 = all cores; batch runs use 1)
  ProgressFn progress;
};

// Errors: the first failing stage's status (file, line, what was expected); with a reference
// instrument, identified right after the piece is set up, its failure (file or set-up unreadable or
// malformed, not identifiable, another machine type: IdentifyInstrumentReference) prefixed "the
// reference instrument (NAME): ".
Result<RunResult> RunPipeline(const PipelineConfig& config, const RunOptions& options = {});

}  // namespace tpcal::pipeline
