// The identification stage: a measured test piece (CMM points, any placement) to machine errors
// with uncertainty. Steps: GD&T evaluation of the piece's inspection plan (datum frame from the
// measured features), every labelled point moved into the nominal part frame and associated with
// the machine state that cut it (testpieces::AssociatePoints), then the point-level
// least-squares identification of kinematics/identification.h.
#pragma once

#include <string>
#include <vector>

#include "core/point_set.h"
#include "core/status.h"
#include "gdt/inspection.h"
#include "kinematics/identification.h"
#include "kinematics/machine_model.h"
#include "testpieces/point_association.h"
#include "testpieces/test_piece.h"

namespace tpcal::pipeline {

struct IdentifyStageOptions {
  std::vector<std::string> parameters;  // empty: testpieces::DefaultParameterSet
  kinematics::IdentifyOptions identify;
};

struct IdentifyStageResult {
  gdt::InspectionResult inspection;
  testpieces::MeasuredObservations observations;
  std::vector<std::string> parameters;
  kinematics::IdentificationResult identification;
};

Result<IdentifyStageResult> RunIdentifyStage(const testpieces::TestPiece& piece,
                                             const kinematics::MachineModel& machine, const PointSet& measured,
                                             const IdentifyStageOptions& options = {});

}  // namespace tpcal::pipeline
