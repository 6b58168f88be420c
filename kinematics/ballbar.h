// Double-ball-bar measurement model (seed 003, Ni et al., eq. 6-9 and 25-28; ISO 230-4 circular
// tests): the bar length of an installation (kinematics/ballbar_setup.h) at a rotary command or a
// path angle, under any ErrorState, through the exact chain (kinematics/forward_kinematics.h).
// Identification is not here.
//
// Commands. The rotary axes are held at the installation's hold_deg (absent: 0) and, for a rotary
// test, the turned axis at `angle_deg`. The linear commands (X, Y, Z) are those that put the tool
// ball on its nominal target on the NOMINAL machine (the controller's program, as on a real test):
//   rotary kinds: target_in_part = w + sense * L0 * d(angle),
//     w the workpiece ball (part frame), L0 the nominal length, d the unit bar direction of the
//     kind (ballbar_setup.h), fixed to the turned element: in the part frame for an axis of the
//     workpiece branch (C table: the tool ball follows the table around), in the tool frame for
//     an axis of the tool branch (B head: the bar turns with the head), so
//     d(angle) = rotation of NominalPartFromTool at `angle` * d_in_tool;
//   circle: the tool ball on the circle of radius L0 about w: the commands that centre the tool
//     ball on w plus L0 (cos phi e1 + sin phi e2), (e1, e2) the plane's linear axes (XY: X, Y;
//     YZ: Y, Z; ZX: Z, X), phi = angle_deg (ISO 230-4; the path direction cw / ccw does not change
//     a servo-free geometry).
// The turned axis line (direction and a point, the frame of its side) is read from the nominal
// chain itself: the part_from_tool motion between the turned axis at 0 and at 90 deg.
//
// Length. length = |ToolPointInPart(errors, commands, tool_ball_in_tool_mm) - w| (mm, exact);
// dl_um = (length - L0) * 1000. On the nominal machine dl = 0 (to the Newton tolerance 1e-9 mm).
#pragma once

#include <Eigen/Core>

#include "core/status.h"
#include "kinematics/axis_state.h"
#include "kinematics/ballbar_setup.h"
#include "kinematics/error_state.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/machine_model.h"

namespace tpcal::kinematics {

// An installation on a machine, its nominal geometry computed once (constant, like MachineModel).
struct BallbarGeometry {
  BallbarInstallation installation;
  AxisState hold;                     // the held rotary commands (rad); linear members 0
  // Rotary kinds only. The frame of the turned side: part frame (workpiece branch) or tool frame
  // (tool branch), with the turned axis at 0.
  bool tool_side = false;             // the turned axis is on the tool branch
  Eigen::Vector3d axis_point_mm = Eigen::Vector3d::Zero();  // a point of the nominal axis line
  Eigen::Vector3d axis_direction = Eigen::Vector3d::UnitZ();  // + command turns the tool + about it
  Eigen::Vector3d bar_direction = Eigen::Vector3d::UnitX();   // unit d (times sense: toward the tool ball)
};

// Errors (kInvalidArgument): a turned or held axis the machine lacks, a radial or tangential
// installation whose ball of the turned side (workpiece ball for a workpiece-branch axis, tool
// ball for a tool-branch axis) lies within 1e-6 mm of the axis line (no radial direction).
Result<BallbarGeometry> MakeBallbarGeometry(const MachineModel& model, const BallbarInstallation& installation);

// The axis commands at `angle_deg` (rotary command or path angle, deg), with t_s set.
// Errors: kNotConverged when the nominal linear commands miss the target by more than 1e-9 mm.
Result<AxisState> BallbarCommand(const MachineModel& model, const BallbarGeometry& geometry, double angle_deg,
                                 double t_s = 0.0);

// The tool ball's nominal target in the part frame at `angle_deg` (mm).
Eigen::Vector3d BallbarTargetInPart(const MachineModel& model, const BallbarGeometry& geometry, double angle_deg);

// Bar length (mm) at `axes` under `errors` (exact chain).
double BallbarLengthMm(const MachineModel& model, const ErrorState& errors, const BallbarGeometry& geometry,
                       const AxisState& axes, Workspace* ws);

// dl = bar length - nominal length at `angle_deg` (um): the `dl_um` of the ball-bar file
// (pipeline/io/ballbar_io.h). Errors: as BallbarCommand.
Result<double> SimulateBallbarDlUm(const MachineModel& model, const ErrorState& errors,
                                   const BallbarGeometry& geometry, double angle_deg, double t_s, Workspace* ws);

}  // namespace tpcal::kinematics
