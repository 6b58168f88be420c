// The instrument-versus-piece table of a diagnosis against an instrument
// (pipeline/diagnosis/reference_agreement.h) as JSON (key "reference_agreement" of the diagnosis
// JSON, docs/formats/diagnosis_json.md), plain text and an HTML table.
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>

#include "pipeline/diagnosis/reference_agreement.h"

namespace tpcal::pipeline {

nlohmann::ordered_json ReferenceAgreementJson(const ReferenceAgreement& a);
std::string ReferenceAgreementText(const ReferenceAgreement& a);
std::string ReferenceAgreementHtml(const ReferenceAgreement& a);

}  // namespace tpcal::pipeline
