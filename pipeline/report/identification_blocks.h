// JSON blocks of tpcal.identification/1 (identify_json.h) that result.json (tpcal.run/1,
// run_json.h) embeds unchanged, so `tpcal identify` and `tpcal run` name every number the same
// way. Include only from .cc files (nlohmann/json).
#pragma once

#include <nlohmann/json.hpp>

#include "kinematics/identification.h"

namespace tpcal::pipeline {

// {"name", "iso_symbol", "identifiable", "unit", "value", "u", "ci95": [lo, hi],
//  "uncertainty": {"analytic": {"u", "ci95", "message"?}, "jackknife": ..., "mc": ...}}.
// value, u and ci95 are null when the parameter is not identifiable (or the method did not run).
nlohmann::ordered_json ParameterEstimateJson(const kinematics::ParameterEstimate& p);

// {"num_parameters", "rank", "condition_number", "singular_values", "not_identifiable",
//  "estimable": [{"combination", "names", "coefficients", "value", "u", "unit"}],
//  "null_directions": ["dy_AR(-90) + dz_AR(-90)", ...]}.
nlohmann::ordered_json IdentifiabilityJson(const kinematics::IdentificationResult& id);
// The same block for any identification (units from `parameters`).
nlohmann::ordered_json IdentifiabilityJson(const kinematics::Identifiability& ident,
                                           const std::vector<kinematics::ParameterEstimate>& parameters);

// {"rms_before_um", "rms_after_um", "sigma_um", "iterations", "termination"}.
nlohmann::ordered_json IdentificationFitJson(const kinematics::IdentificationResult& id);

}  // namespace tpcal::pipeline
