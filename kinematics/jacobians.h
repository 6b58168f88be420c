// Exact Jacobians of the tool pose / tool point in the part frame with respect to active error
// coefficients (automatic differentiation through chain_eval.h; tested against central finite
// differences in three regimes: zero, tiny and random errors).
#pragma once

#include <Eigen/Core>

#include "kinematics/axis_state.h"
#include "kinematics/error_state.h"
#include "kinematics/machine_model.h"

namespace tpcal::kinematics {

// J_point_params (3 x active.size()): d(tool point in part, mm) / d(coefficient, internal units)
// at the current coefficient values. Also returns the point.
Eigen::Vector3d ToolPointJacobian(const MachineModel& model, const ErrorState& errors,
                                  const ActiveSet& active, const AxisState& axes,
                                  const Eigen::Vector3d& contact_in_tool_mm,
                                  Eigen::Matrix<double, 3, Eigen::Dynamic>* J_point_params);

// J_pose_params (6 x active.size()) of part_from_tool: rows 0-2 the translation (mm), rows 3-5
// the rotation vector w (rad) of the perturbation in the part frame, dR = [w]x R.
void PartFromToolJacobian(const MachineModel& model, const ErrorState& errors,
                          const ActiveSet& active, const AxisState& axes,
                          Eigen::Matrix<double, 6, Eigen::Dynamic>* J_pose_params);

}  // namespace tpcal::kinematics
