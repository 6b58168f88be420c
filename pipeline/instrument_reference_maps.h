// The piece against an error-map instrument (probe_artifacts, ballbar; instrument_reference.h),
// and what the two paths of DiagnoseAgainstInstrument share. Internal to the pipeline layer.
#pragma once

#include <string>
#include <vector>

#include "core/point_set.h"
#include "core/status.h"
#include "pipeline/diagnosis/diagnosis.h"
#include "pipeline/identify_stage.h"
#include "pipeline/instrument_reference.h"
#include "pipeline/piece_loader.h"

namespace tpcal::pipeline::instrument_reference_internal {

// The piece identified with `names` (the instrument's), or the caller's identification when its
// parameters are those (any set for maps: `names` empty). Errors: the identification's.
Result<IdentifyStageResult> PieceForReference(const LoadedPiece& setup, const PointSet& measured,
                                              const std::vector<std::string>& names, const std::string& origin,
                                              const DiagnosisOptions& options, const IdentifyStageResult* identified);

// `options` with `reference` as the "sim", named after the instrument's file.
DiagnosisOptions OptionsForReference(const DiagnosisOptions& options, const InstrumentReference& ref,
                                     kinematics::ErrorState reference);

// DiagnoseAgainstInstrument for a reference with maps. Errors: the piece identification's, the
// diagnosis's.
Result<DiagnosisResult> DiagnoseAgainstMaps(const LoadedPiece& setup, const PointSet& measured,
                                            const InstrumentReference& ref, const DiagnosisOptions& options,
                                            const IdentifyStageResult* identified);

}  // namespace tpcal::pipeline::instrument_reference_internal
