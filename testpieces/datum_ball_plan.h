// Plan of a datum-ball test (seed 001): the rotary positions at which the spindle probe (or an
// R-test) centres a ball fixed to the rotary table, and where the ball sits. Seed 001's pattern by
// default: the tilt axis (B on a B/C table, A on an A/C table) at 0, +30 and -30 deg, C every
// 30 deg at each (36 positions). The positions are rotary commands only; the linear commands that
// centre the probe on the ball are what the test reads (kinematics/datum_ball.h).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/status.h"
#include "kinematics/axis_state.h"
#include "kinematics/machine_model.h"

namespace tpcal::testpieces {

struct DatumBallPlanOptions {
  std::vector<double> tilt_deg = {0.0, 30.0, -30.0};  // tilt-axis commands, deg (ISO 841)
  double c_step_deg = 30.0;                           // C from 0 to < 360 in this step, deg
  // Nominal ball centre in the part frame (on the C table), mm: seed 001 Table 1(a)'s R = 200,
  // delta_YW = 0.1, H = 300.
  Eigen::Vector3d ball_part_mm = Eigen::Vector3d(200.0, 0.1, 300.0);
  double ball_diameter_mm = 25.0;  // the sphere probed (its size does not enter the reading)
};

struct DatumBallPlan {
  kinematics::Axis tilt_axis = kinematics::Axis::kB;  // B (bc_table) or A (ac_table)
  std::vector<kinematics::AxisState> positions;       // rotary commands, tilt-major then C
  Eigen::Vector3d ball_part_mm = Eigen::Vector3d::Zero();
  double ball_diameter_mm = 0.0;
};

// The plan on `model` (a B/C or A/C table). Errors: kInvalidArgument for another machine type, no
// tilt angle, a C step outside (0, 360], a tilt outside the tilt axis's stroke, a ball diameter <= 0.
Result<DatumBallPlan> MakeDatumBallPlan(const kinematics::MachineModel& model,
                                        const DatumBallPlanOptions& options = {});

// The linear commands (mm) that centre the probe on the ball at each position of `plan` on the
// error-free `model` (kinematics::BallCentreCommand): what the plan file holds and where the
// probing program touches. Errors: kNotConverged naming the position (1-based).
Result<std::vector<Eigen::Vector3d>> NominalCentringCommands(const kinematics::MachineModel& model,
                                                             const DatumBallPlan& plan);

}  // namespace tpcal::testpieces
