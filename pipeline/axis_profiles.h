// Error-motion and straightness profiles from a measured test piece (issue 5):
//  - turning piece (seed 002 eqs. 22-27): the C-axis radial (um) and tilt (urad) error motion at
//    A = 0 (from S1 over S4) and at A = -90 (from S3 over S6), from the circularity profiles of
//    two faces turned at the same A, matched at equal C (the C command that cut each point);
//  - 3-axis pieces (ISO 10791-7 M1): the straightness of each linear axis seen by straight side
//    faces: for a face cut by moving axis U with its normal along V, the residual deviation
//    (um, signed +V) against the U position (mm) after the identified squareness, with the
//    least-squares reference line removed (ISO 230-1 3.4.8: P-V about the LS line) and the exact
//    minimum-zone value (fitting/minimum_zone.h).
// The profile structs are part of the identify report: pipeline/report/identification_report.h.
#pragma once

#include <string>
#include <vector>

#include "core/status.h"
#include "pipeline/identify_stage.h"
#include "pipeline/report/identification_report.h"

namespace tpcal::pipeline {

// Empty when the piece has no such face pairs (non-turning pieces). Errors: a face pair present
// with fewer than 4 points on a face.
Result<std::vector<CAxisErrorMotion>> CAxisErrorMotions(const testpieces::TestPiece& piece,
                                                        const IdentifyStageResult& stage);

// Straight side faces of a 3-axis piece (machine type xyz): one profile per face with at least
// 5 points whose cut moved one linear axis with the normal along another. Empty otherwise.
Result<std::vector<StraightnessProfile>> LinearAxisStraightness(const testpieces::TestPiece& piece,
                                                                const IdentifyStageResult& stage);

}  // namespace tpcal::pipeline
