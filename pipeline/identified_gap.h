// The gap diagnosis of an identification (pipeline/diagnosis/diagnosis.h) against the model it
// identified: the same base parameters, and every observation the stage associated with its
// nominal slot design, the points its outlier screen left out included. The diagnosis screens them
// again itself, with the verdict's effect in the model (a drift's or a straightness's signature on
// a few points is not a local defect), as Diagnose does. A dense scan's hits flagged inside their
// cells (left out before the cells were valued) head its list of outliers. Shared by `tpcal run`, the gap check of
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
// options.screen_outliers as the stage's; its base set and slot design are set here (noise,
// alpha and a reference are the caller's). Errors: those of DiagnoseObservations.
Result<DiagnosisResult> DiagnoseIdentified(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                                           const IdentifyStageResult& stage, const PointSet& measured,
                                           DiagnosisOptions options);

}  // namespace tpcal::pipeline
