// A measured test piece against an instrument test of the same machine (issue 22, seed 002
// section 4.4): the instrument's raw file is identified first (datum ball: kinematics/datum_ball.h),
// the piece is identified with the same parameters (identify_stage.h), and the two are compared
// parameter by parameter (diagnosis/reference_agreement.h). The piece's gap is then diagnosed
// against the instrument's errors updated by the piece within the instrument's uncertainty
// (kinematics/prior_update.h): a tight instrument is the "sim" as measured, a loose one yields to
// the piece, so its uncertainty cannot raise a false alarm. Nothing is written here.
#pragma once

#include <string>

#include "core/point_set.h"
#include "core/status.h"
#include "pipeline/diagnosis/diagnosis.h"
#include "pipeline/piece_loader.h"

namespace tpcal::pipeline {

struct InstrumentReferenceRequest {
  std::string path;          // the instrument's file (datum_ball: tpcal ballpos v1)
  std::string instrument;    // "datum_ball"
  std::string machine_path;  // the piece's machine file ("" = the nominal machine of its type)
};

// The instruments a reference can come from.
bool IsReferenceInstrument(const std::string& name);

// `options` carry noise, alpha and the screen (reference and base set are set here); `measured`
// is the piece's point file. The result holds reference_agreement. Errors: an unknown instrument
// (kInvalidArgument listing the known ones), the instrument file's and identification's, an
// instrument machine of another type than the piece's, the piece identification's, the diagnosis's.
Result<DiagnosisResult> DiagnoseAgainstInstrument(const LoadedPiece& setup, const PointSet& measured,
                                                  const InstrumentReferenceRequest& request,
                                                  const DiagnosisOptions& options);

}  // namespace tpcal::pipeline
