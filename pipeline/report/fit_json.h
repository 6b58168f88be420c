// JSON of `tpcal fit` (schema "tpcal.fit/1"): every fitted feature with its parameters (units
// in the key names), residual statistics and form value, and every characteristic with its
// values and the features it used. Deterministic: same result, same bytes.
// Schema: README.md, "tpcal fit output".
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>

#include "gdt/inspection.h"

namespace tpcal::pipeline {

// Serialises `result`; `criterion` is "ls" or "mz" (the criterion asked for on the CLI).
std::string FitResultJson(const gdt::InspectionResult& result);
// The same document as a value (for writers that embed it: no text round trip).
nlohmann::ordered_json FitResultJsonValue(const gdt::InspectionResult& result);

}  // namespace tpcal::pipeline
