// The gap diagnosis of an identification (pipeline/diagnosis/diagnosis.h) against the model it
// identified: the same observations, base parameters and nominal slot design, the stage's outlier
// screen carried over as prior. When that reads local_defect and the stage left points out, the
// diagnosis of every point is taken if its verdict's effect explains the patches
// (DiagnosisResult::explained_patches), as Diagnose would. Shared by `tpcal run`, the gap check of
// `tpcal identify` and the diagnosis against an instrument.
#pragma once

#include "core/point_set.h"
#include "core/status.h"
#include "kinematics/machine_model.h"
#include "pipeline/diagnosis/diagnosis.h"
#include "pipeline/identify_stage.h"
#include "testpieces/test_piece.h"

namespace tpcal::pipeline {

// `measured` is the point file the stage read (flagged points get its file lines);
// options.screen_outliers as the stage's; its base set, slot design and prior screen are set
// here (noise, alpha and a reference are the caller's). Errors: those of DiagnoseObservations.
Result<DiagnosisResult> DiagnoseIdentified(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                                           const IdentifyStageResult& stage, const PointSet& measured,
                                           DiagnosisOptions options);

}  // namespace tpcal::pipeline
