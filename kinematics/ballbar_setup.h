// Double-ball-bar set-up files (`tpcal.ballbar_setup/1`, docs/formats/ballbar_setup.md): the
// installations of a ball-bar test (seed 003, Ni et al.; ISO 230-4 circular tests), each named by
// the `setup` column of the ball-bar file (pipeline/io/ballbar_io.h). Geometry only; the
// measurement model is kinematics/ballbar.h.
//
//   schema: tpcal.ballbar_setup/1          # optional; if present must be exactly this
//   installations:
//     - name: C_radial_H1
//       kind: radial                       # radial | tangential | axial | circle
//       axis: C                            # rotary axis turned (C, B, A); circle: plane XY, YZ or ZX
//       workpiece_ball_in_part_mm: [150, 0, 50]
//       tool_ball_in_tool_mm: [0, 0, 0]    # offset from the tool reference point
//       nominal_length_mm: 150
//       sense: -1                          # optional, +1 or -1 (default +1); not for circle
//       hold_deg: {B: 0}                   # optional: the other rotary commands (default 0)
//
// Bar direction (kinematics/ballbar.h): for a rotary test the tool ball sits nominally at
//   workpiece ball + sense * nominal_length * d,
// d the unit direction of `kind` relative to the turned axis line, fixed to the turned element:
//   radial: from the axis line toward the ball of the turned side (perpendicular to the axis);
//   tangential: axis direction x radial; axial: the axis direction (+X / +Y / +Z for A / B / C).
// For `circle` the tool ball runs on a circle of radius nominal_length about the workpiece ball.
#pragma once

#include <Eigen/Core>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/status.h"
#include "kinematics/axis_state.h"

namespace tpcal::kinematics {

enum class BallbarKind { kRadial, kTangential, kAxial, kCircle };
const char* BallbarKindName(BallbarKind k);                          // "radial", ...
std::optional<BallbarKind> BallbarKindFromName(std::string_view name);  // exact names

// Plane of a circular test of two linear axes: the path angle runs from the first axis toward the
// second (XY: from +X toward +Y; YZ: +Y toward +Z; ZX: +Z toward +X).
enum class BallbarPlane { kXY, kYZ, kZX };
const char* BallbarPlaneName(BallbarPlane p);                           // "XY", "YZ", "ZX"
std::optional<BallbarPlane> BallbarPlaneFromName(std::string_view name);

struct BallbarInstallation {
  std::string name;                   // the ball-bar file's `setup` (no comma, no blank at the ends)
  BallbarKind kind = BallbarKind::kRadial;
  Axis axis = Axis::kC;               // rotary axis turned (not for kCircle)
  BallbarPlane plane = BallbarPlane::kXY;  // kCircle only
  Eigen::Vector3d workpiece_ball_in_part_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d tool_ball_in_tool_mm = Eigen::Vector3d::Zero();  // from the tool reference point
  double nominal_length_mm = 100.0;   // > 0; the circle radius for kCircle
  int sense = +1;                     // +1 or -1 (rotary kinds)
  std::map<Axis, double> hold_deg;    // commands of the other rotary axes (absent: 0)
};

struct BallbarSetup {
  std::vector<BallbarInstallation> installations;  // names unique
  // The installation named `name`, or nullptr.
  const BallbarInstallation* Find(std::string_view name) const;
};

// Errors (kParseError, `source:line: message`): malformed YAML, unknown, missing or repeated keys,
// a wrong schema, no installations, a repeated, empty or CSV-unfit name, an unknown kind, an axis
// that is not a rotary axis (rotary kinds) or a plane (circle), a hold of the turned axis or of a
// linear axis, nominal_length_mm <= 0, sense other than +1 / -1 (or given for a circle), a value
// that is not finite. Whether the axes exist on a machine is checked by the model (ballbar.h).
Result<BallbarSetup> ParseBallbarSetup(std::string_view text, const std::string& source);
// The file, then ParseBallbarSetup. Errors also kIoError when it cannot be read.
Result<BallbarSetup> LoadBallbarSetup(const std::string& path);
// The file text of `setup` (17 significant digits), re-read by ParseBallbarSetup to the same set.
std::string FormatBallbarSetup(const BallbarSetup& setup);

// Seed 003's seven C-table installations (samples/ballbar/seed003_setups.yaml's first seven, its
// ASSUMED L1 = 100 mm, L2 = 150 mm, H1 = 50 mm, H3 = 100 mm, 150 mm bar, sense +1), the other
// rotary axis `hold` held at 0 deg (B on seed 003's machine, A on an A/C table).
BallbarSetup Seed003CTableSetup(Axis hold);

}  // namespace tpcal::kinematics
