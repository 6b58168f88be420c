// Plan of an on-machine probing test of artifacts (seed 000): the indexed rotary positions
// A_i x C_j and, at each, the touches on the artifacts the probe can reach. Seed 000's pattern by
// default: A at 0, -30, -60, -90 deg, C every 60 deg, one touch at the centre of every face
// (top and four sides). A touch is left out where the probe would collide (fewer points at
// tilted positions, as seed 000 Fig. 3): a face whose outward normal points down (machine
// frame, n_z < -0.1), or whose approach corridor (the stylus ball swept from `clearance_mm`
// off the face to the contact, then straight up to the safe height) meets another box (inflated
// by the stylus radius) or the table (the part-frame half-space z < table_z_mm).
//
// Corridor, exactly (nominal machine, the stylus vertical: tool along machine +Z; n the face's
// outward normal in the machine frame, c the contact, r the stylus radius): the ball centre moves
// on c + r n -> s = c + (r + clearance_mm) n (checked against every OTHER box), then s -> s +
// 1000 mm machine +Z (checked against every box, the touched one included). A leg is blocked when
// it passes through the interior of a box grown by r along each of its own axes (a slab test;
// grazing within 1e-9 mm does not count) or comes closer than r to the table (part z < table_z_mm
// + r). The first blocked leg names the reason; artifact N is the box's name (its 1-based index
// if the name is empty). The stylus shaft is not modelled (a face with -0.1 <= n_z < 0 overhangs
// it slightly); the NC program (gcode/probe_artifacts_program.h) moves along these corridors.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/status.h"
#include "kinematics/axis_state.h"
#include "kinematics/machine_model.h"
#include "kinematics/probe_artifacts.h"

namespace tpcal::testpieces {

struct ProbeArtifactsPlanOptions {
  std::vector<double> a_deg = {0.0, -30.0, -60.0, -90.0};  // tilt (A) commands, deg, ISO 841
  double c_step_deg = 60.0;                               // C from 0 to < 360 in this step, deg
  double probe_radius_mm = kinematics::kSeed000StylusRadiusMm;  // stylus ball radius
  double clearance_mm = 10.0;      // where each touch starts: this far off the face (ball surface)
  double table_z_mm = 0.0;         // table surface, part frame z
  Status Validate() const;         // kInvalidArgument naming the option
};

struct PlannedTouch {
  kinematics::AxisState rotary;         // a_rad, c_rad set
  int artifact = 0;                     // index into the plan's artifacts
  kinematics::BoxFace face = kinematics::BoxFace::kPlusZ;
  Eigen::Vector3d target_part_mm = Eigen::Vector3d::Zero();  // the face point touched, part frame
  Eigen::Vector3d contact_mm = Eigen::Vector3d::Zero();      // nominal contact, machine frame
  Eigen::Vector3d approach = -Eigen::Vector3d::UnitZ();      // machine frame, unit, toward the face
};

struct SkippedTouch {
  kinematics::AxisState rotary;
  int artifact = 0;
  kinematics::BoxFace face = kinematics::BoxFace::kPlusZ;
  std::string reason;  // "faces down", "corridor meets artifact 2", "corridor meets the table"
};

struct ProbeArtifactsPlan {
  kinematics::ArtifactSet artifacts;
  std::vector<kinematics::AxisState> poses;  // A-major, then C (0 .. < 360)
  std::vector<PlannedTouch> touches;         // pose by pose, box by box, faces in kBoxFaces order
  std::vector<SkippedTouch> skipped;
  double probe_radius_mm = 0.0;
};

// The plan on `model` (an A/C table). Errors: kInvalidArgument for another machine type, options,
// no artifact, an A outside the A stroke, a C step outside (0, 360].
Result<ProbeArtifactsPlan> MakeProbeArtifactsPlan(const kinematics::MachineModel& model,
                                                  const kinematics::ArtifactSet& artifacts,
                                                  const ProbeArtifactsPlanOptions& options = {});

}  // namespace tpcal::testpieces
