// Forward kinematics with exact homogeneous transforms (conventions.h): the pose of the tool in
// the part frame for given axis commands and machine errors. Model/Data split: MachineModel and
// ErrorState are constant; Workspace is the per-call scratch (one per thread).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/frames.h"
#include "kinematics/axis_state.h"
#include "kinematics/error_state.h"
#include "kinematics/machine_model.h"

namespace tpcal::kinematics {

// Per-call scratch. Reuse across calls: it avoids allocation and memoises each link's transform
// (recomputed only when that link's axis position or errors change; safe across models and
// error states). One per thread.
// Memo of one link's last evaluation (an implementation detail of Workspace): the rotations
// derived from its error components are reused while those are bitwise unchanged, and the whole
// transform while the axis position is unchanged too.
struct LinkMemo {
  AxisLink link;            // the link the memo was computed for (a Workspace may be reused)
  bool valid_e = false;
  LinkErrors e{};
  bool has_r = false;
  Eigen::Matrix3d re = Eigen::Matrix3d::Identity();  // R(e_r)
  Eigen::Vector3d k = Eigen::Vector3d::UnitZ();      // R(l_r) a
  bool valid_q = false;
  double q = 0.0;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();   // parent_from_child
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_direction = Eigen::Vector3d::UnitZ();  // actual motion axis, parent frame
  Eigen::Vector3d axis_point = Eigen::Vector3d::Zero();
};

struct Workspace {
  std::vector<LinkErrors> link_errors;  // evaluated error components per link
  std::vector<LinkMemo> memo;           // per link; sized on first use
};

// part_from_tool under `errors` (exact; mm). The model and errors must belong together
// (same machine; asserted).
Rigid3 PartFromTool(const MachineModel& model, const ErrorState& errors, const AxisState& axes,
                    Workspace* ws);
// Nominal machine (no errors).
Rigid3 NominalPartFromTool(const MachineModel& model, const AxisState& axes);
// The same figures through `ws`'s memo of the link transforms: a link is recomputed only when its
// axis position changed (several calls at the same rotary positions compute the rotations once).
Rigid3 NominalPartFromTool(const MachineModel& model, const AxisState& axes, Workspace* ws);

// part_from_machine and machine_from_tool separately (for R-test style checks), under errors.
Rigid3 MachineFromPart(const MachineModel& model, const ErrorState& errors, const AxisState& axes,
                       Workspace* ws);
Rigid3 MachineFromTool(const MachineModel& model, const ErrorState& errors, const AxisState& axes,
                       Workspace* ws);

// A point fixed in the tool frame (e.g. the cutting contact point, mm), in the part frame.
Eigen::Vector3d ToolPointInPart(const MachineModel& model, const ErrorState& errors,
                                const AxisState& axes, const Eigen::Vector3d& contact_in_tool_mm,
                                Workspace* ws);
Eigen::Vector3d NominalToolPointInPart(const MachineModel& model, const AxisState& axes,
                                       const Eigen::Vector3d& contact_in_tool_mm);

// Unit tool axis (+z of the tool frame) in the part frame, nominal.
Eigen::Vector3d NominalToolAxisInPart(const MachineModel& model, const AxisState& axes);

// part_from_tool for explicit link error components (link_errors[link][Component], mm, rad),
// without a Workspace (the functions above evaluate the error terms, then the same chain with
// the Workspace memo; both are tested against an independent 4x4 composition).
Rigid3 PartFromToolWithLinkErrors(const MachineModel& model,
                                  const std::vector<LinkErrors>& link_errors,
                                  const AxisState& axes);

}  // namespace tpcal::kinematics
