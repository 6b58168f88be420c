// Everything `tpcal identify` reports (pipeline/report/identification_report.h): the
// identification stage (identify_stage.h), then for the turning piece the closed form from the
// GD&T items (kinematics equations) and the C-axis error motions, for 3-axis pieces the
// straightness profiles (axis_profiles.h); and the whole of `tpcal identify` from a point file.
// Nothing is written here.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/point_set.h"
#include "core/status.h"
#include "kinematics/machine_model.h"
#include "pipeline/identify_stage.h"
#include "pipeline/raw_scan_labeling.h"
#include "pipeline/report/identification_report.h"
#include "testpieces/test_piece.h"

namespace tpcal::pipeline {

// gap_check: also the diagnosis of the same data against the identified model (identified_gap.h;
// a diagnosis that fails leaves report.gap_check unset). Errors: the stage's, then those of the
// error motions and the straightness profiles.
Result<IdentificationReport> BuildIdentificationReport(const testpieces::TestPiece& piece,
                                                       const kinematics::MachineModel& machine,
                                                       const PointSet& measured,
                                                       const IdentifyStageOptions& options,
                                                       bool gap_check = false);

struct IdentifyRequest {
  std::string points_path{};
  std::vector<std::string> columns{};   // --column ROLE=NAME: a table's column names (ParsePointColumns)
  std::string testpiece = "turning";    // NAME (testpieces/named_pieces.h)
  std::string config_path{};            // "" = NAME's defaults
  std::string machine_path{};           // "" = the piece's nominal machine
  RawScanLabelingOptions labelling{};   // the labelling of a raw scan
  std::vector<std::string> parameters{};  // empty: the piece's standard set
  std::string uncertainty = "all";      // IdentifyOptionsFor: jackknife, analytic, mc or all
  int mc_trials = 2000;
  int subset_trials = 0;                // seed 002's random 3-point subsets per feature (0 = off)
  std::uint64_t seed = 1;               // Monte Carlo and random-subset seed
  bool keep_outliers = false;           // true: flagged points stay in (IdentifyStageOptions::screen_outliers)
  bool gap_check = true;                // diagnose the gap against the identified model (identified_gap.h)
  std::function<void(const std::string& line)> info{};  // progress lines; may be empty
};

// The piece (LoadPiece, its errors prefixed "test piece NAME: "), the point file read and, if it
// is a raw scan, labelled; then BuildIdentificationReport, and with gap_check the diagnosis of the
// same data (report.gap_check; a verdict other than none is also sent to info as a warning).
// Errors: those, in this order (a diagnosis that fails leaves gap_check unset, said to info).
Result<IdentificationReport> IdentifyPointFile(const IdentifyRequest& request);

}  // namespace tpcal::pipeline
