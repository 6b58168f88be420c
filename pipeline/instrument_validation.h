// The validation of the diagnosis (diagnosis/diagnosis_validate.h) against an instrument reference
// (issue 22): each trial's cold machine (its random base errors, geometry only) is measured by the
// virtual instrument (datum_ball: pipeline/datum_ball_simulate_stage.h; probe_artifacts, seed
// 000's artifacts with C every 15 deg: pipeline/probe_artifacts_simulate_stage.h; ballbar, seven
// installations round C holding A at 0 with seed 003's angles: pipeline/ballbar_simulate_stage.h;
// readings or touches with the instrument's noise), the piece is cut by the same machine with one withheld effect switched on,
// measured with CMM noise at a random placement, and diagnosed against the instrument
// (DiagnoseAgainstInstrument, pipeline/instrument_reference.h). The effects, their scaling and the
// table are the engine's. The instrument files are written to a temporary folder, removed after.
#pragma once

#include <string>

#include "core/status.h"
#include "pipeline/diagnosis/diagnosis_validate.h"
#include "pipeline/piece_loader.h"

namespace tpcal::pipeline {

struct InstrumentValidationOptions {
  std::string instrument = "datum_ball";  // or probe_artifacts, ballbar
  double noise_um = 0.5;                  // 1-sigma of each coordinate of a reading (of a touch), um
};

// RunValidation with every piece diagnosed against the instrument test of its cold machine.
// Errors: an unknown instrument (kInvalidArgument listing the known ones), noise not finite or
// < 0, the temporary folder's, RunValidation's; a trial the instrument cannot simulate or identify
// is counted as the verdict "error" with its message.
Result<ValidationSummary> RunInstrumentValidation(const LoadedPiece& setup, ValidationOptions options,
                                                  const InstrumentValidationOptions& instrument);

// Its Markdown (pipeline/diagnose_stage.h ValidationStageMarkdown, the title naming the instrument).
Result<std::string> RunInstrumentValidationStage(const LoadedPiece& setup, const ValidationOptions& options,
                                                 const InstrumentValidationOptions& instrument);

}  // namespace tpcal::pipeline
