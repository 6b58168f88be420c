// The identification stage: a measured test piece (CMM points, any placement) to machine errors
// with uncertainty, the one orchestration of `tpcal identify` and `tpcal run`. Steps: GD&T
// evaluation of the piece's inspection plan (datum frame from the measured features), every
// labelled point moved into the nominal part frame and associated with the machine state that cut
// it (testpieces::AssociatePoints), dense scans pooled into scan-line cells (scan_cells.h), a first
// point-level least-squares identification (kinematics/identification.h) whose re-alignment
// corrects the datum frame, the association again in the corrected frame, and the final
// identification with every uncertainty, its parameters named as they were asked for.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/point_set.h"
#include "core/status.h"
#include "gdt/inspection.h"
#include "kinematics/identification.h"
#include "kinematics/machine_model.h"
#include "kinematics/slot_linearisation.h"
#include "pipeline/diagnosis/outlier_screen.h"
#include "pipeline/scan_cells.h"
#include "testpieces/point_association.h"
#include "testpieces/test_piece.h"

namespace tpcal::pipeline {

struct IdentifyStageOptions {
  std::vector<std::string> parameters;  // empty: testpieces::DefaultParameterSet
  std::string parameters_origin = "--parameters";  // where `parameters` came from: their errors are located there
  kinematics::IdentifyOptions identify;
  ScanCellOptions scan_cells;           // dense scans are pooled (above_points 0: never)
  // A file above scan_cells.above_points is re-aligned (the first pass, with fit_alignment) from
  // an even sample of about this many points, at least 500 per feature or all it has; 0: all.
  std::size_t first_pass_points = 20000;
  // Called as each step starts: "gdt", "associate", "scan cells" (a pooled file identified without
  // fit_alignment: with it, the first pass of a dense file runs on a sample that is not pooled),
  // "identify" (the re-association in the corrected datum frame, and a dense file's pooling, are
  // part of it). May be empty.
  std::function<void(const char* step)> on_step;
  // Outliers and local defects (pipeline/diagnosis/outlier_screen.h) are left out of the final
  // identification and listed; false keeps them (still listed). A dense scan's single hits are
  // screened inside their cells (ScanCellOptions::hit_outlier_z), then its cells by the screen.
  bool screen_outliers = true;
  OutlierScreenOptions screen;
};

struct IdentifyStageResult {
  gdt::InspectionResult inspection;
  testpieces::MeasuredObservations observations;
  std::vector<std::string> parameters;
  kinematics::IdentificationResult identification;
  std::optional<ScanCellSummary> scan_cells;  // set when the observations are scan-line cells
  // The slot linearisation at the nominal machine of `observations` for the base set and every
  // diagnosis candidate: the final identification's first design, and the diagnosis's
  // (DiagnosisOptions::nominal_slot_design with base_parameters = parameters).
  std::shared_ptr<const kinematics::SlotDesign> nominal_slot_design;
  // The outlier screen on the nominal design of the final pass: flagged points (file lines set),
  // left out of `observations` and the identification unless screen_outliers is off; a dense
  // scan's flagged hits first (left out of their cells), then its flagged cells (by their
  // representative point).
  std::vector<ScreenedPoint> outliers;
  std::vector<LocalDefect> local_defects;
  double neighbour_sigma_um = 0.0;
  double neighbour_sigma_dof = 0.0;  // its effective degrees of freedom (OutlierScreen::sigma_dof)
  // Set only when the screen left points out: every observation before it and their nominal slot
  // design, for the diagnosis, which screens them again with an effect in the model
  // (DiagnoseIdentified).
  std::optional<testpieces::MeasuredObservations> unscreened_observations;
  std::shared_ptr<const kinematics::SlotDesign> unscreened_slot_design;
  // The screen's neighbour graph of the observations it judged (unscreened_observations when set,
  // else observations), for the diagnosis's screens (DiagnosisOptions::neighbour_graph).
  std::shared_ptr<const FeatureNeighbourGraph> neighbour_graph;
  // A dense scan's single hits flagged inside their cells (also the first of `outliers`).
  std::vector<ScreenedPoint> flagged_hits;
};

// The identification options of `tpcal identify --uncertainty CHOICE`: jackknife (delete one point,
// and one feature), analytic (Gauss-Newton), mc (GUM S1 Monte Carlo with mc_trials) or anything
// else = all (primary jackknife, Monte Carlo with mc_trials beside it); random_subset_trials and
// the seed as given.
kinematics::IdentifyOptions IdentifyOptionsFor(const std::string& uncertainty, int mc_trials, int subset_trials,
                                               std::uint64_t seed);

// Errors (file:line where a point is at fault): those of gdt::EvaluatePlan and
// testpieces::AssociatePoints (fail policy), unknown parameters (at parameters_origin, listing the
// known names), invalid scan-cell options, and
// those of kinematics::Identify.
Result<IdentifyStageResult> RunIdentifyStage(const testpieces::TestPiece& piece,
                                             const kinematics::MachineModel& machine, const PointSet& measured,
                                             const IdentifyStageOptions& options = {});

}  // namespace tpcal::pipeline
