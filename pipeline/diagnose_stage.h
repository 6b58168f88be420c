// The stage of `tpcal diagnose`: a measured test piece (a raw scan is labelled first) against the
// fitted base model, against machine errors (not refitted), or point by point against a reference
// point file (pipeline/diagnosis/diagnosis.h); and `--validate`, the diagnosis on simulated pieces
// with withheld effects (pipeline/diagnosis/diagnosis_validate.h). Nothing is written here.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>

#include "core/status.h"
#include "pipeline/diagnosis/diagnosis.h"
#include "pipeline/diagnosis/diagnosis_validate.h"
#include "pipeline/piece_loader.h"
#include "pipeline/raw_scan_labeling.h"

namespace tpcal::pipeline {

struct DiagnoseRequest {
  std::string points_path{};
  std::vector<std::string> columns{};  // --column ROLE=NAME: a table's column names (ParsePointColumns)
  std::string testpiece = "turning";  // NAME (testpieces/named_pieces.h)
  std::string config_path{};          // "" = NAME's defaults
  std::string machine_path{};         // "" = the piece's nominal machine
  bool testpiece_given = false;       // NAME was asked for: a configuration must be for that piece
  // "" = the fitted base model; machine errors (.yaml / .yml, tpcal.errors/1) or a point file (an
  // extension ReadPoints knows: .csv, .ply, .pcd, .xyz, .txt)
  std::string reference_path{};
  // With reference_path: the instrument whose raw file it is (datum_ball: tpcal ballpos v1,
  // probe_artifacts: tpcal probepts v1, ballbar: tpcal ballbar v1), identified first and compared
  // with the piece (pipeline/instrument_reference.h); reference_setup its set-up (probe_artifacts:
  // artifacts, optional; ballbar: installations, required).
  std::string reference_instrument{};
  std::string reference_setup{};
  std::optional<double> reference_probe_radius_mm{};  // probe_artifacts: its stylus radius (default 3 mm)
  double noise_um = 0.0;              // known CMM noise sigma; 0 = estimated
  double alpha = 0.01;                // family-wise false-alarm probability of the verdict
  bool keep_outliers = false;         // true: flagged points stay in (DiagnosisOptions::screen_outliers)
  RawScanLabelingOptions labelling{};  // the labelling of a raw scan
  std::function<void(const std::string& line)> info{};  // progress lines; may be empty
};

struct DiagnoseStageResult {
  DiagnosisResult diagnosis;
  // The "inputs" of the diagnosis JSON: points, testpiece (the configuration file if given),
  // machine ("nominal" if none), reference, reference_kind ("points", "machine errors", the
  // instrument's name or ""),
  // noise_um, alpha, keep_outliers ("true" or "false").
  std::map<std::string, std::string> inputs;
};

// The piece and machine of the request. Errors: those of LoadPiece, an unknown NAME worded
// "--testpiece: ... (or --config FILE)".
Result<LoadedPiece> LoadDiagnosisPiece(const DiagnoseRequest& request);

// Errors, in this order: the point file's and the labelling's; a reference of neither kind
// (kInvalidArgument "--reference PATH: expected machine errors (.yaml, .yml) or a point file
// (...)"), the reference file's; the diagnosis's. With reference_instrument: those of
// DiagnoseAgainstInstrument.
Result<DiagnoseStageResult> RunDiagnoseStage(const LoadedPiece& setup, const DiagnoseRequest& request);

// The validation's Markdown: a title line naming the piece, seed, trials, magnitudes (raw or
// visible signature peak) and noise levels (um), a blank line, then ValidationMarkdown. Errors:
// those of RunValidation.
Result<std::string> RunValidationStage(const LoadedPiece& setup, const ValidationOptions& options);

// That Markdown for a summary already run (the title names options.reference_name when set).
std::string ValidationStageMarkdown(const LoadedPiece& setup, const ValidationOptions& options,
                                    const ValidationSummary& summary);

}  // namespace tpcal::pipeline
