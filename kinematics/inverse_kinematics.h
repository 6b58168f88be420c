// Nominal inverse kinematics for planning (test-piece operations, probing plans, NC programs):
// the axis commands that put a tool point at a part-frame point, and the rotary angles that align
// the tool axis with a part-frame direction. Nominal machine only (no errors).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/status.h"
#include "kinematics/axis_state.h"
#include "kinematics/machine_model.h"

namespace tpcal::kinematics {

struct InverseKinematicsOptions {
  bool check_strokes = true;  // fail with kInvalidArgument when a result is outside a stroke
};

// Linear axes X, Y, Z such that the tool point `contact_in_tool_mm` (tool frame) lies at
// `point_in_part_mm` with the rotary axes, t_s and op of `rotary` kept. Exact for every machine
// type (the nominal chain is affine in X, Y, Z for fixed rotary axes). Table machines:
// X, Y, Z = machine_from_part(A, C) * p_part for a zero contact offset.
Result<AxisState> NominalAxesForToolPoint(const MachineModel& model,
                                          const Eigen::Vector3d& point_in_part_mm,
                                          const AxisState& rotary,
                                          const Eigen::Vector3d& contact_in_tool_mm = Eigen::Vector3d::Zero(),
                                          const InverseKinematicsOptions& options = {});

// Rotary positions (A or B, and C) that put the tool axis (+z of the tool frame) along the unit
// part-frame direction `tool_axis_in_part`: zero, one or two solutions (tilt of either sign;
// at zero tilt, C = `c_hint_rad`). Only the rotary fields are set. xyz: the only solution is
// the vertical axis (0, 0, 1); other directions give kInvalidArgument. Strokes are checked when
// options.check_strokes; solutions outside are dropped (kInvalidArgument if none remains).
Result<std::vector<AxisState>> RotaryAnglesForToolAxis(const MachineModel& model,
                                                       const Eigen::Vector3d& tool_axis_in_part,
                                                       double c_hint_rad = 0.0,
                                                       const InverseKinematicsOptions& options = {});

}  // namespace tpcal::kinematics
