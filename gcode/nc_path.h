// A tool path as a control executes it: the sequence of rapid, feed and arc moves with their
// end positions, read back from NC text (gcode/nc_reader.h), from LinuxCNC's canonical output
// (gcode/rs274_canon.h) or taken from the IR itself. Paths of different dialects are compared
// in the PART frame (tool reference point through the nominal kinematics, or as programmed
// under tool centre point control), which is what the machined piece sees.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/status.h"
#include "gcode/ir.h"
#include "kinematics/machine_model.h"

namespace tpcal::gcode {

enum class PathMoveKind { kRapid, kFeed, kArc };
const char* PathMoveKindName(PathMoveKind k);

struct PathMove {
  PathMoveKind kind = PathMoveKind::kRapid;
  // X, Y, Z (mm), A, B, C (deg) at the end of the move as the control sees them: machine axes,
  // or, when `tcp`, X, Y, Z are the tool tip in the part frame (work offset = part frame).
  std::array<double, 6> end{};
  bool tcp = false;
  // Arcs: plane 17 (XY), 18 (XZ), 19 (YZ); absolute centre in that plane's (first, second)
  // axes (XY: X, Y; XZ: Z, X as LinuxCNC prints it; YZ: Y, Z); rotation +n counter-clockwise,
  // -n clockwise (n >= 1 turns, LinuxCNC's convention).
  int plane = 17;
  double center1_mm = 0.0, center2_mm = 0.0;
  int rotation = 0;
  std::string label;  // block label ("N120", Heidenhain line "37")
  bool probe = false; // a probing feed (rs274 STRAIGHT_PROBE): it stops on contact
};

struct NcPath {
  std::vector<PathMove> moves;
  double tool_length_offset_mm = 0.0;  // last length offset the program applied, if known
  int tool_changes = 0;
};

// The path the IR commands (rapids, feeds, arcs; drill cycles expanded as G85 with G98 / G99;
// table-turning moves as one straight feed each; probe moves as a feed to their target), in
// machine axes, starting at the origin.
NcPath ExpectedPath(const IrProgram& prog);

// A path point in the part frame.
struct PartPoint {
  PathMoveKind kind = PathMoveKind::kRapid;
  Eigen::Vector3d tip_mm = Eigen::Vector3d::Zero();  // tool reference point, part frame
  double a_deg = 0.0, b_deg = 0.0, c_deg = 0.0;
  Eigen::Vector3d arc_center_mm = Eigen::Vector3d::Zero();  // arcs, part frame
  int rotation = 0;
  std::string label;
};

// Part-frame points of a path; zero-length moves dropped, consecutive collinear straight moves
// of the same kind and rotary position merged (a move split into segments, e.g. LinuxCNC's
// constant-surface-speed steps, compares equal to the unsplit move).
std::vector<PartPoint> ToPartPoints(const NcPath& path, const kinematics::MachineModel& machine,
                                    double merge_tol_mm = 1e-4);

struct PathComparison {
  int points = 0;
  double max_tip_deviation_mm = 0.0;
  double max_rotary_deviation_deg = 0.0;
  double max_center_deviation_mm = 0.0;
  std::string worst_label;  // of the second path
};
// Compares point by point. Errors (kInvalidArgument) name both labels: different counts,
// kinds, rotations, or a deviation above tol_mm / tol_deg.
Result<PathComparison> ComparePaths(const std::vector<PartPoint>& reference, const std::vector<PartPoint>& other,
                                    double tol_mm, double tol_deg);

}  // namespace tpcal::gcode
