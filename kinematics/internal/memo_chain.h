// The double-precision chain with a per-Workspace memo of each link's transform (used by
// forward_kinematics.cc and simulate.cc; tested against the templated chain and the 4x4
// reference). A link is recomputed only when its axis position or its error components change.
#pragma once

#include <vector>

#include "kinematics/chain_eval.h"
#include "kinematics/forward_kinematics.h"

namespace tpcal::kinematics::internal {

// machine_from_part and machine_from_tool for link errors `e`; with `axes_out` (num_links()
// entries) also each link's actual motion axis in the machine frame (as BranchPosesT).
void MemoBranchPoses(const MachineModel& model, const std::vector<LinkErrors>& e,
                     const AxisState& axes, Workspace* ws, PoseT<double>* machine_from_part,
                     PoseT<double>* machine_from_tool, LinkAxisT<double>* axes_out);

}  // namespace tpcal::kinematics::internal
