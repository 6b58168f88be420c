// Output of the diagnosis: the `tpcal.diagnosis/1` JSON (docs/formats/diagnosis_json.md; the keys
// there in that form, plus documented extras) and a readable report (plain text and HTML).
#pragma once

#include <map>
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "pipeline/diagnosis/diagnosis.h"

namespace tpcal::pipeline {

// `inputs` are written under "inputs" (points file, test piece, machine, options, seed): the
// effective configuration beside the result.
std::string DiagnosisJson(const DiagnosisResult& result, const std::map<std::string, std::string>& inputs = {});
// The same document as a value (for writers that embed it: no text round trip).
nlohmann::ordered_json DiagnosisJsonValue(const DiagnosisResult& result,
                                          const std::map<std::string, std::string>& inputs = {});

// Plain-text report: gap, groups standing out, candidate table, verdict, aliasing, unobservable families.
std::string DiagnosisText(const DiagnosisResult& result);

// Self-contained HTML page with the same content.
std::string DiagnosisHtml(const DiagnosisResult& result, const std::string& title);

}  // namespace tpcal::pipeline
