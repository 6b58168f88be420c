// JSON of `tpcal identify` (schema "tpcal.identification/1", README "tpcal identify output"):
//   {"schema", "testpiece", "machine", "points_source", "n_points", "n_features",
//    "parameters": [{"name", "iso_symbol", "value", "unit", "u", "ci95": [lo, hi],
//                    "identifiable", "uncertainty": {"analytic": {"u", "ci95"}, ...}}],
//    "identifiability": {"rank", "num_parameters", "condition_number", "singular_values",
//                        "not_identifiable", "estimable": [{"combination", "value", "u", "unit"}],
//                        "null_directions": [...]},
//    "fit": {"rms_before_um", "rms_after_um", "sigma_um", "iterations", "termination"},
//    "alignment": {"rotation", "translation_mm"},
//    "closed_form": {...} (turning piece: solver (a) from the GD&T items),
//    "error_motion": [...] (turning piece: C radial/tilt profiles), "straightness": [...] (3-axis)}
// A parameter the data cannot separate has "identifiable": false and null value, u and ci95.
// Deterministic: same inputs, same bytes.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "kinematics/seed002_closed_form.h"
#include "pipeline/axis_profiles.h"
#include "pipeline/identify_stage.h"

namespace tpcal::pipeline {

struct IdentificationReport {
  explicit IdentificationReport(IdentifyStageResult s) : stage(std::move(s)) {}
  std::string testpiece;
  std::string machine;
  IdentifyStageResult stage;
  kinematics::Seed002Items items;                          // turning piece: the GD&T items used
  std::optional<kinematics::ClosedFormResult> closed_form;  // turning piece
  std::vector<CAxisErrorMotion> error_motion;
  std::vector<StraightnessProfile> straightness;
};

// Runs everything `tpcal identify` reports: the identification stage, then for the turning piece
// the closed form (kinematics equations) and the C error motions, for 3-axis pieces the
// straightness profiles. Errors: the stage's.
Result<IdentificationReport> BuildIdentificationReport(const testpieces::TestPiece& piece,
                                                       const kinematics::MachineModel& machine,
                                                       const PointSet& measured,
                                                       const IdentifyStageOptions& options);

std::string IdentificationJson(const IdentificationReport& report);

}  // namespace tpcal::pipeline
