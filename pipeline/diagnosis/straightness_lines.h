// Straightness candidates in the ISO 230-1 convention: a straightness error motion is measured
// from its reference line, so each polynomial power q^k (k >= 2) of a straightness candidate is
// replaced by q^k minus its least-squares line a + b q over the axis positions at which the
// piece's points were cut. The line (an offset and a squareness) is the base model's; without it
// a Z^2 term over Z = 40-90 mm is mostly a Z squareness, and modelling the effect would move the
// identified squareness by what the data cannot attribute. Internal to the diagnosis library.
#pragma once

#include <Eigen/Core>
#include <map>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "kinematics/error_state.h"
#include "kinematics/identification.h"

namespace tpcal::pipeline::diagnosis_internal {

// The straightness symbols whose candidates are centred (E_YX, E_ZX, E_XY, E_ZY, E_XZ, E_YZ).
const std::vector<std::string>& StraightnessSymbols();

// The errors_yaml effect item of the power 0 and 1 terms of `symbol` (the reference line).
std::string ReferenceLineItem(const std::string& symbol);

// In J (columns = `coefficients` of `errors` over `observations`), every polynomial column of
// power >= 2 of a term labelled with a key of `line_columns` (its power 0 and power 1 columns in
// J) minus its least-squares line in the term's argument over the observations.
void RemoveReferenceLines(std::span<const kinematics::Observation> observations, const kinematics::ErrorState& errors,
                          const std::vector<int>& coefficients,
                          const std::map<std::string, std::pair<int, int>>& line_columns, Eigen::MatrixXd* J);

}  // namespace tpcal::pipeline::diagnosis_internal
