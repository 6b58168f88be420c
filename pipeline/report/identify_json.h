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

#include <string>

#include "pipeline/report/identification_report.h"

namespace tpcal::pipeline {

std::string IdentificationJson(const IdentificationReport& report);

}  // namespace tpcal::pipeline
