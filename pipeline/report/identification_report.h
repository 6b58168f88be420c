// What `tpcal identify` reports (pipeline/identify_report.h builds it; identify_json.h and
// identify_summary.h write it): the identification, and beside it for the turning piece the
// closed form from the GD&T items and the C-axis error motions, for 3-axis pieces the
// straightness profiles of the linear axes (pipeline/axis_profiles.h computes both profiles).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "kinematics/identification.h"
#include "kinematics/seed002_closed_form.h"
#include "pipeline/diagnosis/gap_check.h"
#include "pipeline/diagnosis/outlier_screen.h"

namespace tpcal::pipeline {

struct CAxisErrorMotion {
  std::string name;            // "C at A=0", "C at A=-90"
  std::string faces;           // "S1 over S4"
  double a_deg = 0.0;
  kinematics::ErrorMotionProfile profile;
};

struct StraightnessProfile {
  std::string name;            // "E_YX" (straightness of X in Y direction, ISO 230-1 symbol)
  std::string feature;         // the face it comes from
  std::string moving_axis;     // "X"
  std::string direction;       // "Y"
  std::vector<double> position_mm;   // moving-axis command of each point, sorted
  std::vector<double> deviation_um;  // residual along +direction, LS line removed
  double pv_ls_um = 0.0;       // max - min about the LS line
  double mz_um = 0.0;          // minimum-zone straightness
  bool mz_certified = false;
  double slope_urad = 0.0;     // the LS line's slope (angular deviation seen by this face)
};

struct IdentificationReport {
  explicit IdentificationReport(kinematics::IdentificationResult id) : identification(std::move(id)) {}
  std::string testpiece;      // the piece's name
  std::string machine;        // the machine type's name
  std::string points_source;  // the point file the GD&T was evaluated from
  kinematics::IdentificationResult identification;
  kinematics::Seed002Items items;                          // turning piece: the GD&T items used
  std::optional<kinematics::ClosedFormResult> closed_form;  // turning piece
  std::vector<CAxisErrorMotion> error_motion;
  std::vector<StraightnessProfile> straightness;
  // The outlier screen of the identification (pipeline/diagnosis/outlier_screen.h).
  std::vector<ScreenedPoint> outliers;
  std::vector<LocalDefect> local_defects;
  double neighbour_sigma_um = 0.0;
  // The gap diagnosis of the same data (pipeline/diagnosis/gap_check.h); unset when not run.
  std::optional<GapCheck> gap_check;
};

}  // namespace tpcal::pipeline
