// The text `tpcal run` prints on stdout: one row per identified parameter (name, short ISO 230-1
// symbol, value, u (k = 1), 95 % interval, unit; um and urad with fixed decimals, polynomial
// coefficients (um per mm^k) with 4 significant digits, a parameter the data cannot separate as
// "n/a ... not identifiable"), then the rank, condition number and residual RMS (um), then the
// gap diagnosis in one line (and the instrument-versus-piece line of a diagnosis against an instrument).
#pragma once

#include <optional>
#include <string>

#include "core/status.h"
#include "kinematics/identification.h"
#include "pipeline/diagnosis/diagnosis.h"

namespace tpcal::pipeline {

// The header row, one row per parameter and "rank R of N, condition number C; residual RMS B um -> A um".
std::string RunParameterTable(const kinematics::IdentificationResult& identification);

// "instrument vs piece: N of M compared parameters disagree (NAME, ...)" when the diagnosis was made
// against an instrument (reference_agreement set; the names of the disagreeing rows, if any), else "".
std::string InstrumentAgreementLine(const std::optional<ReferenceAgreement>& agreement);

// "gap diagnosis: FAMILY (NAME), shrink S % (cross-validated C %)" for a diagnosis (then the
// instrument line above when there is one); without one,
// "gap diagnosis: not made: WHY" when it was asked for, else "". Each line ends in a newline.
std::string GapDiagnosisLine(const std::optional<DiagnosisResult>& diagnosis, bool asked, const Status& why_not);

// "identification: N point(s) left out by the outlier screen (P in K local defect(s); ...)" (or
// "flagged and kept" under --keep-outliers) when the identification's screen flagged any, else "".
std::string IdentificationScreenLine(const std::vector<ScreenedPoint>& flagged, const std::vector<LocalDefect>& patches);

}  // namespace tpcal::pipeline
