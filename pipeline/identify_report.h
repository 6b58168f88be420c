// Everything `tpcal identify` reports (pipeline/report/identification_report.h): the
// identification stage (identify_stage.h), then for the turning piece the closed form from the
// GD&T items (kinematics equations) and the C-axis error motions, for 3-axis pieces the
// straightness profiles (axis_profiles.h). Nothing is written here.
#pragma once

#include "core/point_set.h"
#include "core/status.h"
#include "kinematics/machine_model.h"
#include "pipeline/identify_stage.h"
#include "pipeline/report/identification_report.h"
#include "testpieces/test_piece.h"

namespace tpcal::pipeline {

// Errors: the stage's, then those of the error motions and the straightness profiles.
Result<IdentificationReport> BuildIdentificationReport(const testpieces::TestPiece& piece,
                                                       const kinematics::MachineModel& machine,
                                                       const PointSet& measured,
                                                       const IdentifyStageOptions& options);

}  // namespace tpcal::pipeline
