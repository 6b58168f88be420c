// Loading an inspection plan from YAML (schema tpcal.inspection_plan/1, gdt/PLAN_FORMAT.md).
// Strict: unknown or duplicate keys, wrong types, non-finite numbers, unknown kinds and dangling
// feature references are errors with "file:line: what was expected" (lines from yaml-cpp
// marks, 1-based). yaml-cpp stays inside plan_yaml.cc.
#pragma once

#include <string>
#include <string_view>

#include "core/status.h"
#include "gdt/plan.h"

namespace tpcal::gdt {

// Parses plan text; `source` names it in messages and becomes InspectionPlan::source.
// Errors: kParseError (YAML syntax, schema), kInvalidArgument (ValidatePlan).
Result<InspectionPlan> ParseInspectionPlan(std::string_view text, const std::string& source);

// Reads and parses a plan file. Errors: kIoError if it cannot be read, then as above.
Result<InspectionPlan> LoadInspectionPlan(const std::string& path);

}  // namespace tpcal::gdt
