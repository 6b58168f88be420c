// The point reference of DiagnoseAgainstPoints (diagnosis.h): each measured observation matched
// with a reference observation of the same feature label, by order within the feature when both
// have the same number of points and every pair's nominal positions lie within the tolerance,
// otherwise by the nearest nominal position (ties: the first in file order) within it. Internal
// to the diagnosis library.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/point_set.h"
#include "pipeline/diagnosis/diagnosis.h"
#include "testpieces/point_association.h"

namespace tpcal::pipeline::diagnosis_internal {

struct ReferenceMatching {
  std::vector<long> match;  // per measured observation: its reference observation, -1 for none
  DiagnosisResult::ReferenceMatch summary;  // `unmatched` is counted by KeepMatched
};

// Matches `measured` with `reference` (nominal positions, part frame, within tol_mm).
ReferenceMatching MatchReferencePoints(const testpieces::MeasuredObservations& measured,
                                       const testpieces::MeasuredObservations& reference, double tol_mm);

// The matched measured observations (features renumbered in first-use order) and the
// reference's normal deviation at each one's match (*dev_um); every unmatched point is counted
// in matching->summary.unmatched and listed in *skipped ("file:line: no reference point ...",
// `points` being the measured point file).
testpieces::MeasuredObservations KeepMatched(const testpieces::MeasuredObservations& measured, const PointSet& points,
                                             const Eigen::VectorXd& reference_dev_um, double tol_mm,
                                             ReferenceMatching* matching, std::vector<double>* dev_um,
                                             std::vector<std::string>* skipped);

}  // namespace tpcal::pipeline::diagnosis_internal
