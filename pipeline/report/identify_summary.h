// The text `tpcal identify` prints on stdout: the fit (points, features, residual RMS before and
// after, sigma, um), one row per parameter (value, the analytic and jackknife uncertainties, the
// 95 % interval, the ISO 230-1 symbol; those the data cannot separate marked), identifiability
// (rank, condition number, the determined combinations), C error motions and straightness.
#pragma once

#include <string>

#include "pipeline/report/identification_report.h"

namespace tpcal::pipeline {

std::string IdentificationSummary(const IdentificationReport& report);

}  // namespace tpcal::pipeline
