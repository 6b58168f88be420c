// Identification from an on-machine probing test of artifacts (seed 000): the table pose at
// every indexed position (kinematics/table_poses.h), then the position-dependent error maps of
// the A and C axes (kinematics/error_map_separation.h), with covariance propagated from the
// touches through both linear steps.
#pragma once

#include <span>

#include "core/status.h"
#include "kinematics/error_map_separation.h"
#include "kinematics/machine_model.h"
#include "kinematics/probe_artifacts.h"
#include "kinematics/table_poses.h"

namespace tpcal::kinematics {

struct ProbeArtifactsResult {
  TablePoseFit poses;
  ErrorMaps maps;
};

// Errors: those of FitTablePoses and SeparateTablePoses.
Result<ProbeArtifactsResult> IdentifyProbeArtifacts(const MachineModel& model, const ArtifactSet& artifacts,
                                                    std::span<const ProbeTouch> touches,
                                                    const TablePoseOptions& options = {});

}  // namespace tpcal::kinematics
