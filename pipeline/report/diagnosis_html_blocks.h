// HTML blocks of the diagnosis shared by the run report (pipeline/report_html.cc) and
// `tpcal diagnose --html` (diagnosis_json.cc): what the verdict names beyond its leading family,
// the machine errors without and with the named effect modelled (both u), and the outlier
// screen's listing. Each returns "" when it has nothing to show; text is XML-escaped.
#pragma once

#include <string>

#include "pipeline/diagnosis/diagnosis.h"

namespace tpcal::pipeline {

// <p>: every family the verdict names (two effects, a local defect beside one), and for
// unexplained the best partial candidates.
std::string VerdictFamiliesHtml(const Verdict& verdict);

// <table id="base-shift-table">: the verdict's candidate's base_shift (identified errors without
// and with the effect modelled, each +- u, k = 1); "" for none, local_defect and unexplained.
std::string BaseShiftHtml(const DiagnosisResult& result);

// <table id="screen-table">: the local defects (feature, points, peak and mean um, centre mm,
// lines), the patches the verdict's effect explains, then the flagged points (at most 50 listed), with the neighbour sigma and whether they
// were left out.
std::string ScreenHtml(const DiagnosisResult& result);

}  // namespace tpcal::pipeline
