// The outlier screen's listing (pipeline/diagnosis/outlier_screen.h) in the JSON and text
// reports of identify, diagnose and run: `outliers` (line, feature, kind, deviation_um, reason,
// left_out) and `local_defects`. Include only from .cc files (it pulls in nlohmann/json).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pipeline/diagnosis/outlier_screen.h"

namespace tpcal::pipeline {

nlohmann::ordered_json OutliersJson(const std::vector<ScreenedPoint>& points);
nlohmann::ordered_json LocalDefectsJson(const std::vector<LocalDefect>& defects);

// One patch as text: its points, peak, mean, span, centre (part frame, mm) and file lines.
std::string PatchText(const LocalDefect& d);

// Text lines: each patch, then the flagged points (at most 10 listed), with the noise sigma.
std::string ScreenText(const std::vector<ScreenedPoint>& points, const std::vector<LocalDefect>& defects,
                       double sigma_um);

}  // namespace tpcal::pipeline
