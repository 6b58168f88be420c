// The machining process of a test piece as a controller-neutral program: operations (one tool,
// one paper / standard step each), passes (one spindle setting, the features they finish) and
// moves (axis targets in machine commands, feeds, durations). gcode/ turns this into NC text;
// the time stamps t_s of the probing plan come from the same moves.
//
// Axis values follow kinematics/conventions.h (ISO 841): X, Y, Z place the TOOL REFERENCE POINT
// in the MCS (milling tools: tip centre on the tool axis; turning inserts: the centre of the nose
// radius), A and C are rotary commands. During table turning (SpindleMode::kTableTurning) the C
// axis spins as a spindle and the `c_rad` of the moves is meaningless (left 0).
//
// Times: cutting moves at their programmed feed; rapids at ProcessModel::rapid_mm_per_min on the
// longest linear axis and rotary_rapid_deg_per_s on the rotary axes (whichever is slower); a tool
// change costs tool_change_s; starting a table-turning spindle costs spindle_start_s. This is an
// estimate good to seconds, which is what thermal drift terms (time constants of minutes) need.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/status.h"
#include "kinematics/axis_state.h"

namespace tpcal::testpieces {

enum class ToolKind {
  kEndMill,         // flat end mill (corner_radius_mm = 0) or radius end mill (corner radius > 0)
  kFaceMill,        // face mill with inserts; cuts with its flat end
  kReamer,          // finishes a hole while feeding along its axis
  kTurningInsert,   // non-rotating turning tool, nose radius corner_radius_mm
  kTouchProbe,      // spindle touch probe: diameter_mm is its stylus ball's (measuring programs)
};
const char* ToolKindName(ToolKind k);  // "end_mill", "face_mill", "reamer", "turning_insert", "touch_probe"

struct Tool {
  int number = 1;                  // T number in the NC program
  std::string name;                // "radius end mill d8 R0.5"
  ToolKind kind = ToolKind::kEndMill;
  double diameter_mm = 0.0;        // cutting diameter (0 for a turning insert)
  double corner_radius_mm = 0.0;   // end mill corner radius / insert nose radius
  double flute_length_mm = 0.0;    // axial length of the cutting edge
  int teeth = 1;
  double included_angle_deg = 0.0; // turning insert included angle (80 deg rhombic: C type)
  double gauge_length_mm = 0.0;    // spindle gauge line to the tool reference point
  std::string material;            // "carbide"
  double radius_mm() const { return 0.5 * diameter_mm; }
};

enum class SpindleMode {
  kOff,
  kMilling,       // the tool rotates at speed_rpm (M03 clockwise seen from the spindle when
                  // `clockwise`)
  kTableTurning,  // the tool is locked (oriented); the C table spins; constant surface speed
                  // surface_speed_m_per_min (G96) clamped at max_speed_rpm, or speed_rpm if the
                  // surface speed is 0
};
const char* SpindleModeName(SpindleMode m);  // "off", "milling", "table_turning"

struct Spindle {
  SpindleMode mode = SpindleMode::kOff;
  double speed_rpm = 0.0;
  double surface_speed_m_per_min = 0.0;  // table turning (G96); 0: constant speed_rpm
  double max_speed_rpm = 0.0;            // table turning clamp
  bool clockwise = true;                 // milling: M03; turning: table turns +C (positive)
  // Table speed (rpm) when the tool cuts at `radius_mm` from the C axis.
  double TableRpmAt(double radius_mm) const;
};

enum class MoveKind {
  kRapid,       // G0 to `end`
  kLinear,      // G1 to `end` (all axes interpolated; during table turning: feed per rev)
  kArc,         // G2 / G3 in the machine XY plane (G17) about arc_center_xy_mm, ending at `end`;
                // full circle when start == end
  kToolChange,  // M6 to `tool`
  kDwell,       // G4 (e.g. spindle start), duration_s
};
const char* MoveKindName(MoveKind k);

struct Move {
  MoveKind kind = MoveKind::kRapid;
  kinematics::AxisState start;  // commands at the start (the previous move's end)
  kinematics::AxisState end;    // target commands; end.t_s = time at the end of the move, end.op
  Eigen::Vector2d arc_center_xy_mm = Eigen::Vector2d::Zero();  // kArc: centre, machine XY
  bool clockwise = false;     // kArc: G2 (true) or G3 (false), seen from +Z
  double arc_angle_rad = 0.0; // kArc: swept angle (> 0), 2 pi for a full circle
  double feed_mm_per_min = 0.0;  // kLinear / kArc while milling (tool reference point)
  double feed_mm_per_rev = 0.0;  // kLinear while table turning
  // kLinear while table turning: distance of the tool reference point from the C axis at the
  // start and end of the move (mm); the table speed follows Spindle::TableRpmAt.
  double turn_radius_start_mm = 0.0, turn_radius_end_mm = 0.0;
  bool cutting = false;          // the move removes finishing stock
  double start_time_s = 0.0;
  double duration_s = 0.0;
};

struct Pass {
  std::string name;                  // "B_R floor", "S1 axial"
  Spindle spindle;
  std::vector<std::string> features; // features this pass finishes
  std::vector<Move> moves;           // in program order; the first starts at the pass start
  double start_time_s = 0.0;
  double end_time_s = 0.0;
};

struct Operation {
  int number = 0;                    // 1-based: the contract's `op` column
  std::string name;                  // "groove", "holes", "turn S1/B1"
  std::string description;           // the step of the paper / standard it implements
  Tool tool;
  std::vector<Pass> passes;
  double start_time_s = 0.0;
  double end_time_s = 0.0;
};

// Machine constants of the time estimate (see the file comment).
struct ProcessModel {
  double rapid_mm_per_min = 20000.0;
  double rotary_rapid_deg_per_s = 90.0;
  double tool_change_s = 8.0;
  double spindle_start_s = 3.0;
  Status Validate() const;
};

// Builds the moves of a program with times. Keeps the current axis state; every Add* appends a
// move to the current pass and advances the clock.
class ProgramBuilder {
 public:
  explicit ProgramBuilder(const ProcessModel& process);
  // Where the machine stands before the first move (a safe position); no time passes.
  void SetStartState(const kinematics::AxisState& state) { state_ = state; }

  // Starts operation `name` with `tool` (adds a tool change when the tool number changes).
  void BeginOperation(const std::string& name, const std::string& description, const Tool& tool);
  // Starts a pass with its spindle (a dwell of spindle_start_s when the spindle setting changes).
  void BeginPass(const std::string& name, const Spindle& spindle, std::vector<std::string> features);
  void Rapid(const kinematics::AxisState& target);
  // Milling feed move (mm/min of the tool reference point; rotary axes interpolated, time from
  // the part-frame path length given by the caller if > 0, else the linear-axis length).
  void Linear(const kinematics::AxisState& target, double feed_mm_per_min, bool cutting,
              double path_length_mm = 0.0);
  // Table-turning feed move: linear axes only; the time integrates the table speed over the
  // distance of the tool reference point from the C axis, linear from start to end radius (mm).
  void TurnLinear(const kinematics::AxisState& target, double feed_mm_per_rev,
                  double start_radius_mm, double end_radius_mm, bool cutting);
  // Arc in the machine XY plane about `center_xy_mm` through `angle_rad` (> 0), ending at the
  // point reached; Z unchanged.
  void Arc(const Eigen::Vector2d& center_xy_mm, double angle_rad, bool clockwise,
           double feed_mm_per_min, bool cutting);
  void Dwell(double seconds);

  const kinematics::AxisState& state() const { return state_; }
  double time_s() const { return state_.t_s; }
  // Index of the last move of the current pass (for cut models that refer to it).
  int last_move_index() const;
  int current_operation() const { return static_cast<int>(ops_.size()); }
  int current_pass_index() const;
  // Ends the program and returns the operations (times closed).
  std::vector<Operation> Finish();

 private:
  void Append(Move m);
  ProcessModel process_;
  kinematics::AxisState state_;
  std::vector<Operation> ops_;
  int current_tool_ = -1;
};

// Time (s, from program start) at which a move passes the fraction `f` in [0, 1] of its way
// (of its length, or of its angle for arcs); table-turning moves integrate the surface-speed law
// of `spindle` (the move's pass spindle).
double TimeAtFraction(const Move& move, double f, const Spindle& spindle);

// Total program time (s).
double ProgramDuration(const std::vector<Operation>& ops);

}  // namespace tpcal::testpieces
