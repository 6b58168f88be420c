// The identification stage: a measured test piece (CMM points, any placement) to machine errors
// with uncertainty. Steps: GD&T evaluation of the piece's inspection plan (datum frame from the
// measured features), every labelled point moved into the nominal part frame and associated with
// the machine state that cut it (testpieces::CutPointAtDatum), then the point-level
// least-squares identification of kinematics/identification.h.
#pragma once

#include <string>
#include <vector>

#include "core/point_set.h"
#include "core/status.h"
#include "gdt/inspection.h"
#include "kinematics/identification.h"
#include "kinematics/machine_model.h"
#include "testpieces/test_piece.h"

namespace tpcal::pipeline {

struct MeasuredObservations {
  std::vector<kinematics::Observation> observations;  // group = index into feature_names
  std::vector<std::string> feature_names;
  std::vector<std::size_t> point_index;  // index into the PointSet of each observation
};

// Labelled points of `measured` (CMM frame) as identification observations, using the datum
// frame `datum_from_cmm`. Points of features the piece does not have, and unlabelled points,
// are errors naming the point file line; so is a point no cut of its feature reaches.
Result<MeasuredObservations> ObservationsFromPoints(const testpieces::TestPiece& piece, const PointSet& measured,
                                                    const Rigid3& datum_from_cmm);

// The parameter set identified by default on `piece` with `machine`: the seed 002 Table 2 set
// and the X-Y squareness E_C(0X)Y for the turning piece on an A/C table; for M2 the straightness of X in Z (E_ZX.c2, E_ZX.c3,
// um per mm^2 and mm^3); the ISO 230-1 location set otherwise.
std::vector<std::string> DefaultParameterSet(const testpieces::TestPiece& piece,
                                             const kinematics::MachineModel& machine);

struct IdentifyStageOptions {
  std::vector<std::string> parameters;  // empty: DefaultParameterSet
  kinematics::IdentifyOptions identify;
};

struct IdentifyStageResult {
  gdt::InspectionResult inspection;
  MeasuredObservations observations;
  std::vector<std::string> parameters;
  kinematics::IdentificationResult identification;
};

Result<IdentifyStageResult> RunIdentifyStage(const testpieces::TestPiece& piece,
                                             const kinematics::MachineModel& machine, const PointSet& measured,
                                             const IdentifyStageOptions& options = {});

}  // namespace tpcal::pipeline
