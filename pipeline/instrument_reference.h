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
#include "pipeline/reference_instruments.h"

namespace tpcal::pipeline {

struct InstrumentReferenceRequest {
  // The instrument's file (datum_ball: tpcal ballpos v1, identified here), or an identification
  // tpcal wrote (.json, tpcal.identification/1: its parameters as they are, the instrument named
  // there; any measurement type or test piece).
  std::string path;
  std::string instrument;    // "datum_ball" for a raw file; ignored for .json
  std::string machine_path;  // the piece's machine file ("" = the nominal machine of its type)
};

// A reference that is an identification tpcal wrote (by its extension, .json).
bool IsIdentificationReference(const std::string& path);

// `options` carry noise, alpha and the screen (reference and base set are set here); `measured`
// is the piece's point file. The result holds reference_agreement. Errors: an unknown instrument
// for a raw file (kInvalidArgument listing the known ones), the instrument file's and
// identification's (pipeline/io/identification_reader.h for .json), a reference machine of
// another type than the piece's, the piece identification's, the diagnosis's.
Result<DiagnosisResult> DiagnoseAgainstInstrument(const LoadedPiece& setup, const PointSet& measured,
                                                  const InstrumentReferenceRequest& request,
                                                  const DiagnosisOptions& options);

}  // namespace tpcal::pipeline
