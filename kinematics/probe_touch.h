// The virtual touch of an on-machine probing test (seed 000): where the touch-trigger probe
// reports contact with an artifact face at an indexed rotary position under any tpcal error
// model (kinematics/probe_artifacts.h for the geometry and the reported quantities).
//
// Model. The probe moves along the machine-frame line of linear commands c(s) = c0 + s d, d the
// nominal approach direction (-(nominal part-to-machine rotation) x face normal), c0 the nominal
// probe-centre command of the planned contact. Under `errors` the probe centre in the part frame
// is ToolPointInPart(errors, {c(s), rotary}, 0); the ball touches the face when that centre is
// `probe_radius_mm` from the face's plane (normal . q = offset + r), solved for s by Newton. The
// reported contact is c(s) + (r + pretravel) d: the trigger's uncompensated pre-travel (um)
// delays the reading along the approach, a constant plus a three-lobed term over the approach's
// azimuth in the machine XY plane (as a kinematic-resistive probe): p0 + p3 |d_xy| cos(3 phi),
// phi = atan2(d_y, d_x); the lobing scales with the approach's horizontal component |d_xy|, so it
// fades to nothing as the approach turns vertical: a vertical approach gets only p0.
#pragma once

#include <Eigen/Core>

#include "core/status.h"
#include "kinematics/axis_state.h"
#include "kinematics/error_state.h"
#include "kinematics/machine_model.h"
#include "kinematics/probe_artifacts.h"

namespace tpcal::kinematics {

struct TouchOptions {
  double probe_radius_mm = kSeed000StylusRadiusMm;  // stylus ball radius
  double pretravel_um = 0.0;         // p0, uncompensated constant pre-travel
  double pretravel_lobing_um = 0.0;  // p3, three-lobed pre-travel amplitude
  Status Validate() const;           // kInvalidArgument: radius <= 0, a value not finite
};

// The contact point (machine frame, mm) the probe reports touching `face` at the part-frame point
// `target_part_mm` (on the face's nominal plane) at `rotary` under `errors`. Errors:
// kInvalidArgument (options), kNotConverged (no contact within 20 Newton steps to 1e-9 mm, or
// the approach runs parallel to the face under the errors).
Result<Eigen::Vector3d> SimulateTouch(const MachineModel& model, const ErrorState& errors,
                                      const AxisState& rotary, const FaceGeometry& face,
                                      const Eigen::Vector3d& target_part_mm, const TouchOptions& options);

}  // namespace tpcal::kinematics
