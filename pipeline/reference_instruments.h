// The instruments whose raw files tpcal identifies as a reference for a test piece (`diagnose
// --reference-instrument`, the pipeline YAML's `reference.instrument`): one list for the parsers
// and the stage.
#pragma once

#include <string>

namespace tpcal::pipeline {

inline constexpr const char* kReferenceInstruments = "datum_ball";  // for messages: "expected ..."

inline bool IsReferenceInstrument(const std::string& name) { return name == "datum_ball"; }

}  // namespace tpcal::pipeline
