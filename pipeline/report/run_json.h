// result.json of `tpcal run` (schema "tpcal.run/1"): every number of the run with the effective
// configuration, tpcal version, git revision and seed. Deterministic: the same report gives
// the same bytes (no time stamps, no timings, no absolute paths beyond those configured).
//
// {
//   "schema": "tpcal.run/1", "tpcal": {"version", "git_revision"}, "seed": 1,
//   "config": {... the effective tpcal.pipeline/1 settings ...},
//   "input": {"points", "format", "digest_xxh64", "num_points" (in the file), "source_units",
//             "raw_scan" (only for a file without labels: {"num_points", "num_labelled",
//             "num_rejected", "labelled_fraction", "rms_distance_um", "symmetry_order",
//             "part_from_cmm", "points_per_feature": {...}, "message"})},
//   "piece": "...", "machine": "...",
//   "inspection": {... tpcal.fit/1 (fit_json.h) ...},
//   "identification": {... the blocks of tpcal.identification/1 (identify_json.h,
//     identification_blocks.h) under the same keys: "n_points", "n_features",
//     "parameters": [{"name", "iso_symbol", "identifiable", "unit", "value", "u", "ci95",
//        "uncertainty": {"analytic": {"u", "ci95"}, ...}, "primary_method",
//        "truth" (only with a stated truth)}],
//     "identifiability": {..., "estimable": [{"combination", ...}], "null_directions": [...]},
//     "fit": {"rms_before_um", "rms_after_um", "sigma_um", "iterations", "termination"},
//     "alignment": {"rotation", "translation_mm"}},
//   "figures": ["machine_errors", ...],
//   "diagnosis": {... tpcal.diagnosis/1 (docs/formats/diagnosis_json.md) ...}
//                (or {"error": "..."} when it could not be made; absent with diagnose: false)
// }
#pragma once

#include <string>

#include "pipeline/report/run_report.h"

namespace tpcal::pipeline {

std::string RunReportJson(const RunReport& report);

}  // namespace tpcal::pipeline
