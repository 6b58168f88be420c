// The stage of `tpcal fit`: CMM points to fitted features and GD&T. The plan is a tpcal.inspection_plan/1
// file, else the test piece's (which also labels a raw scan by its nominal features), else an
// ad-hoc plan of every labelled feature in the CMM frame (kinds from `types` or the normals).
// Least-squares (ISO 10360-6) fits, or minimum zone with criterion "mz". Nothing is written here.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/status.h"
#include "gdt/inspection.h"
#include "pipeline/raw_scan_labeling.h"

namespace tpcal::pipeline {

struct FitRequest {
  std::string points_path;
  std::string plan_path;           // "" = the piece's plan, or ad hoc
  std::vector<std::string> types;  // FEATURE=KIND (line2, line3, plane, circle, cylinder, sphere, cone, point)
  std::string criterion;           // "" (as planned), ls or mz: the form criterion of every feature
  int threads = 0;                 // point parser threads (0 = all cores)
  std::vector<std::string> columns;  // --column ROLE=NAME: a table's column names (ParsePointColumns)
  std::string testpiece;           // optional NAME; with it a configuration and a machine file
  std::string config_path;
  std::string machine_path;
  RawScanLabelingOptions labelling;  // with testpiece: the labelling of a raw scan
  std::function<void(const std::string& line)> info;  // progress lines; may be empty
};

// Errors, in this order: the point file's, a malformed --type, the piece's (LoadPiece) and the
// labelling's, --config / --machine without --testpiece, a raw scan without a piece, the plan
// file's, a --type feature the plan lacks, an ad-hoc plan the points cannot make, the evaluation's.
Result<gdt::InspectionResult> RunFitStage(const FitRequest& request);

// The text `tpcal fit` prints: one row per feature (kind, points, RMS and form in um), then one
// per characteristic with its values.
std::string FitSummary(const gdt::InspectionResult& result);

}  // namespace tpcal::pipeline
