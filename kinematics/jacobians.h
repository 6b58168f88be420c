// Exact Jacobians of the tool pose / tool point in the part frame with respect to active error
// coefficients or error slots (the tool point: a double chain and forward-mode differentiation of
// each link that moves; the pose: automatic differentiation through chain_eval.h). Tested against
// central finite differences in four regimes (zero, tiny, random, large errors) and against
// forward mode through the whole chain.
#pragma once

#include <Eigen/Core>
#include <span>

#include "kinematics/axis_state.h"
#include "kinematics/conventions.h"
#include "kinematics/error_state.h"
#include "kinematics/machine_model.h"

namespace tpcal::kinematics {

// J_point_params (3 x active.size()): d(tool point in part, mm) / d(coefficient, internal units)
// at the current coefficient values. Also returns the point.
Eigen::Vector3d ToolPointJacobian(const MachineModel& model, const ErrorState& errors,
                                  const ActiveSet& active, const AxisState& axes,
                                  const Eigen::Vector3d& contact_in_tool_mm,
                                  Eigen::Matrix<double, 3, Eigen::Dynamic>* J_point_params);

// One error component of one axis link (conventions.h): the derivative variables of a
// linearisation per slot, which every coefficient's column is a combination of.
struct ErrorSlot {
  Axis axis = Axis::kX;
  Component component = Component::kTx;
  friend bool operator==(const ErrorSlot&, const ErrorSlot&) = default;
};

// J_point_slots (3 x slots.size()): d(tool point in part, mm) / d(slot, mm or rad) at the current
// errors, for slots of axes the machine has. Also returns the point.
Eigen::Vector3d ToolPointSlotJacobian(const MachineModel& model, const ErrorState& errors, const AxisState& axes,
                                      const Eigen::Vector3d& contact_in_tool_mm, std::span<const ErrorSlot> slots,
                                      Eigen::Matrix<double, 3, Eigen::Dynamic>* J_point_slots);

// J_pose_params (6 x active.size()) of part_from_tool: rows 0-2 the translation (mm), rows 3-5
// the rotation vector w (rad) of the perturbation in the part frame, dR = [w]x R.
void PartFromToolJacobian(const MachineModel& model, const ErrorState& errors,
                          const ActiveSet& active, const AxisState& axes,
                          Eigen::Matrix<double, 6, Eigen::Dynamic>* J_pose_params);

}  // namespace tpcal::kinematics
