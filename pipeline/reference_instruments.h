// The instruments whose raw files tpcal identifies as a reference for a test piece (`diagnose
// --reference-instrument`, the pipeline YAML's `reference.instrument`): one list for the parsers
// and the stage. probe_artifacts and ballbar identify error maps; their set-up is
// `--reference-setup` (`reference.setup`): the artifacts (optional) and the installations (required).
#pragma once

#include <string>

namespace tpcal::pipeline {

// For messages: "expected ...".
inline constexpr const char* kReferenceInstruments = "datum_ball, probe_artifacts or ballbar";

inline bool IsReferenceInstrument(const std::string& name) {
  return name == "datum_ball" || name == "probe_artifacts" || name == "ballbar";
}

// The instruments that take a set-up file (probe_artifacts: tpcal.artifacts/1, ballbar:
// tpcal.ballbar_setup/1).
inline bool ReferenceTakesSetup(const std::string& name) { return name == "probe_artifacts" || name == "ballbar"; }

}  // namespace tpcal::pipeline
