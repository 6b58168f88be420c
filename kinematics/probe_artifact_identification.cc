#include "kinematics/probe_artifact_identification.h"

namespace tpcal::kinematics {

Result<ProbeArtifactsResult> IdentifyProbeArtifacts(const MachineModel& model, const ArtifactSet& artifacts,
                                                    std::span<const ProbeTouch> touches,
                                                    const TablePoseOptions& options) {
  Result<TablePoseFit> poses = FitTablePoses(model, artifacts, touches, options);
  TPCAL_RETURN_IF_ERROR(poses);
  Result<ErrorMaps> maps = SeparateTablePoses(model, *poses, poses->dof);
  TPCAL_RETURN_IF_ERROR(maps);
  return ProbeArtifactsResult{std::move(*poses), std::move(*maps)};
}

}  // namespace tpcal::kinematics
