// A measured test piece against an instrument test of the same machine (issue 22, seed 002
// section 4.4): the instrument's raw file is identified first, then
//  * datum ball (kinematics/datum_ball.h) or an identification tpcal wrote (.json): location
//    errors and squareness. The piece is identified with the same parameters (identify_stage.h),
//    the two are compared parameter by parameter (diagnosis/reference_agreement.h), and the
//    piece's gap is diagnosed against the instrument's errors updated by the piece within the
//    instrument's uncertainty (kinematics/prior_update.h): a tight instrument is the "sim" as
//    measured, a loose one yields to the piece, so its uncertainty cannot raise a false alarm.
//  * probe_artifacts (seed 000) or ballbar (seed 003): error maps of the rotary axes (error
//    motions at the measured angles, tables), which no parameter of the piece's model names. The
//    "sim" is the instrument's tpcal.errors/1 (what `identify --errors-out` writes: the maps,
//    entries the instrument cannot determine at 0) on the piece's machine, as measured. Their own
//    uncertainty enters the diagnosis's base model (DiagnosisOptions::reference_uncertainty):
//    the directions along which the maps' covariance (the full one of a probing test identified
//    here, else u per entry) moves the piece's deviations by more than its noise are fitted with
//    the re-alignment, and what it adds below that is expected in the gap's tests, so a noisy
//    instrument raises no alarm and a loose one leaves the piece less to say.
//    The piece is identified with its own parameters and every point
//    (its own screen would flag what its model lacks and the maps hold); the diagnosis screens
//    against the maps. The piece's parameters are compared with the maps' parameter equivalent
//    (kinematics/map_location_equivalent.h; probe_artifacts: with the linear axes' squareness it
//    fits, `parameters`), the piece's side being the equivalent plus the piece's own fit on top
//    of the maps; those the two disagree on are refitted on top of the maps as measured, those
//    the instrument cannot see are fitted from the piece (instrument_reference_maps.h). A ball
//    bar's maps have no equivalent (no component along the location errors): nothing is
//    compared, the table says why, and the two meet through the simulated piece only.
// Nothing is written here.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/point_set.h"
#include "core/status.h"
#include "kinematics/error_state.h"
#include "kinematics/identification.h"
#include "pipeline/diagnosis/diagnosis.h"
#include "pipeline/identify_stage.h"
#include "pipeline/piece_loader.h"
#include "pipeline/reference_instruments.h"

namespace tpcal::pipeline {

struct InstrumentReferenceRequest {
  // The instrument's raw file (datum_ball: tpcal ballpos v1; probe_artifacts: tpcal probepts v1;
  // ballbar: tpcal ballbar v1), identified here, or an identification tpcal wrote (.json,
  // tpcal.identification/1: its parameters as they are, the instrument named there).
  std::string path;
  std::string instrument;    // kReferenceInstruments for a raw file; ignored for .json
  // probe_artifacts: its artifacts (tpcal.artifacts/1; "" = seed 000's three columns); ballbar:
  // its installations (tpcal.ballbar_setup/1, required); datum_ball: must be "".
  std::string setup_path;
  std::string machine_path;  // the piece's machine file ("" = the nominal machine of its type)
  std::optional<double> probe_radius_mm{};  // probe_artifacts: its stylus ball radius (default 3 mm); others: unset
};

// The instrument's result, on the piece's machine.
struct InstrumentReference {
  std::string instrument;  // "datum_ball", "probe_artifacts", "ballbar", or the .json's
  std::string source;      // request.path
  std::string machine_type;  // of the instrument's machine ("" when a .json names none)
  // Location errors and squareness (datum ball, .json): compared parameter by parameter. With
  // maps: the constant errors identified with them (probe_artifacts: the linear axes' squareness),
  // already in `maps` at their values.
  std::vector<kinematics::ParameterEstimate> parameters;
  // Their covariance (display units, `parameters`' order) when the datum ball was identified here
  // or its .json carries one ("parameter_covariance"); empty otherwise (u alone, correlations unknown).
  Eigen::MatrixXd parameter_covariance;
  // Error maps (probe_artifacts, ballbar): the instrument's errors as measured.
  std::optional<kinematics::ErrorState> maps;
  int map_entries = 0;                       // node values the instrument reports
  // Their standard uncertainties (display units, k = 1) by ErrorState coefficient name, for the
  // entries the instrument determined; empty when unknown (a .json reference).
  std::vector<std::pair<std::string, double>> map_u;
  // Their full covariance (display units, in the coefficient order of `maps`), when the instrument
  // was identified here (probe_artifacts); empty otherwise (map_u alone, correlations unknown).
  Eigen::MatrixXd map_covariance;
  std::vector<std::string> not_identifiable;  // map entries it cannot determine (written as 0)
  std::vector<std::string> map_undetermined;  // the same, as coefficient names of `maps`
  std::vector<std::string> not_separable;     // ballbar: families the maps carry no component of
  // ballbar identified here: errors it does not model but folds into the maps in part (the linear
  // axes' squareness), and per map entry its value per display unit of each
  // (kinematics::BallbarMapResponse). The instrument puts no bound on them.
  std::vector<std::string> map_unmodelled;
  std::vector<std::pair<std::string, Eigen::RowVectorXd>> map_unmodelled_response;
};

// A reference that is an identification tpcal wrote (by its extension, .json).
bool IsIdentificationReference(const std::string& path);

// Identifies the instrument's file. Errors: an unknown instrument for a raw file
// (kInvalidArgument listing the known ones), a set-up given to datum_ball or missing for ballbar,
// the instrument file's, set-up's and identification's (file:line), a .json's
// (pipeline/io/identification_reader.h), a reference machine of another type than the piece's.
Result<InstrumentReference> IdentifyInstrumentReference(const LoadedPiece& setup,
                                                        const InstrumentReferenceRequest& request);

// `options` carry noise, alpha and the screen (reference and base set are set here); `measured`
// is the piece's point file. `identified`: the piece already identified by the caller (tpcal run)
// with the same options; used when its parameters are the ones the comparison needs (the
// instrument's; for maps, any, when its screen flagged nothing). The result holds reference_agreement. Errors: the piece
// identification's, the diagnosis's.
Result<DiagnosisResult> DiagnoseAgainstInstrument(const LoadedPiece& setup, const PointSet& measured,
                                                  const InstrumentReference& reference,
                                                  const DiagnosisOptions& options,
                                                  const IdentifyStageResult* identified = nullptr);
// IdentifyInstrumentReference, then the above; its errors first.
Result<DiagnosisResult> DiagnoseAgainstInstrument(const LoadedPiece& setup, const PointSet& measured,
                                                  const InstrumentReferenceRequest& request,
                                                  const DiagnosisOptions& options);

// The parameters of `params` the piece disagrees with: a disagreeing row's members (the
// parameter itself, or the parameters of a combination), matched by name exactly.
std::set<std::string> DisagreeingParameters(const ReferenceAgreement& agreement,
                                            const std::vector<kinematics::ParameterEstimate>& params);

}  // namespace tpcal::pipeline
