// Configuration of `tpcal run` (schema tpcal.pipeline/1), from a PIPELINE.yaml or from flags.
// Relative paths inside a YAML file are taken relative to the file's directory, except `out`,
// which (like every command-line path) is relative to the current directory.
//
//   schema: tpcal.pipeline/1                # optional; if present must be this
//   testpiece: turning                      # piece kind (its defaults) or a tpcal.testpiece/1 file
//   points: ../turning/cmm_points.csv       # measured points (tpcal points v1 CSV, PLY, PCD, xyz)
//   machine: ../machines/ac_table.yaml      # optional: tpcal.machine/1; default the nominal machine
//                                           #   of the piece kind (ac_table for turning / cone)
//   parameters: [dx_CR(0), ...]             # optional: coefficients to identify (default: the
//                                           #   piece's standard set, pipeline/identify_stage.h)
//   seed: 1                                 # Monte Carlo seed, written to every output
//   uncertainty: {primary: jackknife_points, jackknife_groups: true, monte_carlo_trials: 2000}
//   diagnose: true                          # gap diagnosis (pipeline/diagnosis/diagnosis.h) against the identified model
//   truth: ../turning/truth.yaml            # optional: stated truth of a simulated sample (report marks)
//   reference: {instrument: datum_ball, file: ballpos.csv}  # optional: the diagnosis against an
//                                           #   instrument test of the same machine (instrument_reference.h);
//                                           #   probe_artifacts / ballbar: also setup: PATH (artifacts, optional;
//                                           #   installations, required)
//   raw_scan: {anchor_feature: H1, anchor_near_mm: [120, -80, 40]}  # optional: for a raw scan of a
//                                           #   symmetric piece, the feature nearest this CMM point
//   scan_cells: {above_points: 250000, target_cells: 100000, max_cell_mm: 4, max_cell_deg: 2}
//                                           # dense scans: scan-line cells (pipeline/scan_cells.h)
//   report: {position_magnification: 1000, profile_magnification: 10000}
//   out: out/turning                        # optional output directory (the CLI's --out wins)
// Unknown keys are errors naming the key and its line.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/status.h"
#include "kinematics/identification.h"
#include "pipeline/scan_cells.h"
#include "pipeline/report/svg_figures.h"

namespace tpcal::pipeline {

struct PipelineConfig {
  std::string source;       // the YAML file ("" when built from flags)
  std::string testpiece = "turning";
  std::string points;
  // A table's column names for the roles feature, x, y, z, i, j, k (PointReadOptions::columns);
  // empty: the contract names and their aliases. YAML columns: {feature: Name, x: X}.
  std::vector<std::pair<std::string, std::string>> columns;
  std::string machine;      // "" = nominal machine of the piece kind
  std::vector<std::string> parameters;
  std::uint64_t seed = 1;
  kinematics::UncertaintyMethod primary = kinematics::UncertaintyMethod::kJackknifePoints;
  bool jackknife_groups = true;
  int monte_carlo_trials = 2000;
  bool diagnose = true;
  // false: probe hits and patches the outlier screen flags are left out of identification and
  // diagnosis (listed with the reason); true keeps them (still listed). YAML keep_outliers.
  bool keep_outliers = false;
  std::string truth;        // "" = none
  // An instrument test of the same machine the diagnosis is made against
  // (pipeline/instrument_reference.h); "" = none, both set or neither. YAML reference:
  // {instrument: datum_ball, file: PATH, setup: PATH, probe_radius_mm: R}; `tpcal run --reference PATH
  // --reference-instrument NAME [--reference-setup S.yaml] [--reference-probe-radius-mm R]`.
  // reference_setup: probe_artifacts' artifacts (tpcal.artifacts/1, "" = seed 000's), ballbar's
  // installations (required); reference_probe_radius_mm: probe_artifacts' stylus (unset = 3 mm).
  std::string reference_instrument;
  std::string reference_file;
  std::string reference_setup;
  std::optional<double> reference_probe_radius_mm;
  // Raw scans of a symmetric piece: the labelling placing `anchor_feature` nearest
  // `anchor_near_mm` (scan frame, mm) is chosen (raw_scan_labeling.h). YAML:
  // raw_scan: {anchor_feature: H1, anchor_near_mm: [x, y, z]}; `tpcal run --anchor H1@x,y,z` overrides it.
  std::string anchor_feature;
  std::optional<Eigen::Vector3d> anchor_near_mm;
  // Dense scans: consecutive points of a scan line pooled into cells before identification and
  // diagnosis (scan_cells.h); above_points: 0 turns it off.
  ScanCellOptions scan_cells;
  FigureOptions figures;
  std::string out;

  Status Validate() const;
};

// Reads a pipeline YAML. Errors: kIoError (unreadable), kParseError (syntax, unknown keys,
// wrong types: file and line). Values are checked by Validate() (RunPipeline calls it), after
// the command line has overridden what it overrides; a batch file need not name `points`.
Result<PipelineConfig> LoadPipelineConfig(const std::string& path);
Result<PipelineConfig> ParsePipelineConfig(const std::string& yaml_text, const std::string& source);
// What `tpcal run`'s flags set over the pipeline file; empty or unset members leave it as it is.
struct PipelineOverrides {
  std::string testpiece{};
  std::string points{};
  std::vector<std::string> columns{};  // --column ROLE=NAME values: non-empty replaces the file's columns
  std::string machine{};
  std::string truth{};
  std::vector<std::string> parameters{};
  std::optional<std::uint64_t> seed{};
  std::optional<int> monte_carlo_trials{};
  bool keep_outliers = false;  // --keep-outliers: true sets keep_outliers, false leaves the file's
  std::string reference_file{};        // non-empty: replaces the reference's file
  std::string reference_instrument{};  // non-empty: replaces the reference's instrument
  std::string reference_setup{};       // non-empty: replaces the reference's set-up
  std::optional<double> reference_probe_radius_mm{};  // set: replaces the reference's stylus radius
  std::string out{};
  std::string anchor_feature{};  // non-empty: replaces raw_scan's anchor_feature and anchor_near_mm
  std::optional<Eigen::Vector3d> anchor_near_mm{};
};

// `config` (a loaded file, or the defaults) with the overrides applied; a batch, whose points come
// from its inputs, gets the placeholder points "(batch)" when it names none. Errors: Validate()'s,
// then no output directory (kInvalidArgument "no output directory: give --out DIR (or 'out' in the
// pipeline file)").
Result<PipelineConfig> ApplyPipelineOverrides(PipelineConfig config, const PipelineOverrides& overrides, bool batch);

// The effective configuration as YAML (every key, defaults included) for outputs.
std::string FormatPipelineConfig(const PipelineConfig& config);

std::optional<kinematics::UncertaintyMethod> ParseUncertaintyMethod(const std::string& name);

}  // namespace tpcal::pipeline
