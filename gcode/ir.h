// The one intermediate representation of a machining program between the test piece
// (testpieces::Operation / Pass / Move) and the dialect posts: a flat list of instructions
// (rapid, linear, arc, drill cycle, index A/C, C as a turning spindle, tool change, spindle,
// coolant, work offset, dwell, touch-probe move), each remembering the test-piece move it comes
// from. Measuring programs (the datum-ball test, gcode/datum_ball_program.h) use the same IR.
//
// Coordinates are those of the test piece's moves (kinematics/conventions.h): X, Y, Z place the
// tool reference point in the MCS, whose origin is the work offset's origin (seed 002: the
// nominal A/C intersection, so G54 = the pivot); A, C in rad inside, degrees in the NC text.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/status.h"
#include "gcode/options.h"
#include "kinematics/axis_state.h"
#include "testpieces/test_piece.h"

namespace tpcal::gcode {

enum class InstrKind {
  kOperationStart,  // comment block: op number, name, description, tool
  kWorkOffset,      // select work_offset (G54.. / preset)
  kToolChange,      // tool (posted number, length compensation on)
  kSpindleOn,       // milling spindle: spindle_rpm, spindle_clockwise
  kSpindleOff,
  kCoolantOn,
  kCoolantOff,
  kRapid,           // to `end`; `axis_mask` says which words are meaningful (initial moves)
  kIndex,           // rotary-only positioning to `end` (A, C)
  kLinear,          // feed move to `end` (feed_mode)
  kArc,             // circular feed to `end` about the arc centre in arc_plane (G17 XY; G18 ZX, G19 YZ:
                    // measuring programs only, the backplot, safety and path checks read XY arcs)
  kDrillCycle,      // reaming cycle (G85 / CYCLE85 / CYCL DEF 201), see DrillCycle
  kTableSpinStart,  // C table as a turning spindle, see TableSpin
  kTableSpinStop,   // C back to axis mode; its position is unknown afterwards
  kDwell,           // dwell_s
  kProbe,           // touch-probe move from `start` toward `end` along probe.direction, see ProbeMove
  kProgramStop,     // M0: the operator's step (`text`: what to do, e.g. mount the ball bar); axes stay
  kProgramEnd,
};
const char* InstrKindName(InstrKind k);

// Plane of an arc: G17 (XY, the angle from +X toward +Y), G18 (ZX: +Z toward +X), G19 (YZ: +Y toward
// +Z); counter-clockwise (G03, Heidenhain DR+) is the positive sense of that angle.
enum class ArcPlane { kXY, kZX, kYZ };

enum class FeedMode {
  kPerMinute,       // feed_mm_per_min of the tool reference point
  kPerRevolution,   // feed_mm_per_rev of the table (table turning)
  kInverseTime,     // simultaneous rotary + linear move: the block takes duration_s
};

// Reaming / boring cycle with feed in and feed out (Fanuc and LinuxCNC G85, Sinumerik CYCLE85,
// Heidenhain CYCL DEF 201). Machine Z values of the tool reference point (tool along +Z).
struct DrillCycle {
  double x_mm = 0.0, y_mm = 0.0;
  double initial_z_mm = 0.0;   // where the tool stands before the cycle (G98 return level)
  double r_z_mm = 0.0;         // rapid approach level (R plane = surface + clearance)
  double surface_z_mm = 0.0;   // hole entry surface (Sinumerik RFP, Heidenhain Q203)
  double bottom_z_mm = 0.0;
  double feed_mm_per_min = 0.0;
  double retract_feed_mm_per_min = 0.0;
  double dwell_s = 0.0;
  bool return_to_initial = true;  // G98 (true) or G99 (return to R)
};

// C table as a turning spindle for one pass (seed 002 table turning).
struct TableSpin {
  double surface_speed_m_per_min = 0.0;  // 0: constant rpm
  double max_rpm = 0.0;                   // clamp actually used (piece and c_spindle.max_rpm)
  double rpm = 0.0;                       // constant-speed fallback: speed at reference_radius_mm
  double reference_radius_mm = 0.0;       // largest cutting radius of the pass
  bool positive_c = true;                 // the table turns in +C (ISO 841)
  kinematics::Axis radius_axis = kinematics::Axis::kX;  // machine axis along the C-axis radius
                                                         // (G96 P / SCC[axis])
  bool radius_axis_exact = false;         // the radius is exactly |that axis value| for all moves
  double feed_mm_per_rev = 0.0;
};

// One touch of a touch probe: a feed move from `start` (the approach point) toward `end` (the
// expected contact plus an overtravel) that stops when the stylus triggers (LinuxCNC G38.2, Fanuc
// G31, Sinumerik MEAS=1, Heidenhain TCH PROBE 0 along one machine axis, cycle 4 MEASURING IN 3-D
// along any other direction). Machine axes.
struct ProbeMove {
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // unit, machine frame: the probing direction
  Eigen::Vector3d contact_mm = Eigen::Vector3d::Zero();  // tool reference point at the nominal contact
  int result = 0;  // 1-based touch number within its position (Heidenhain result parameter Q<n>)
};

struct Instr {
  InstrKind kind = InstrKind::kRapid;
  kinematics::AxisState start;  // motion: axis commands before and after (IR coordinates)
  kinematics::AxisState end;
  unsigned axis_mask = 0x3F;    // bit i: axis i (X Y Z A B C) is commanded (rapids)

  FeedMode feed_mode = FeedMode::kPerMinute;
  double feed_mm_per_min = 0.0;
  double feed_mm_per_rev = 0.0;
  double duration_s = 0.0;      // from the test piece's time model
  double tip_path_mm = 0.0;     // five-axis: length of the tool tip path in the part frame

  Eigen::Vector2d arc_center_xy_mm = Eigen::Vector2d::Zero();
  double arc_center_z_mm = 0.0;  // arcs in G18 / G19: the centre's Z (its X or Y from arc_center_xy_mm)
  ArcPlane arc_plane = ArcPlane::kXY;
  bool clockwise = false;
  double arc_angle_rad = 0.0;

  double turn_radius_start_mm = 0.0, turn_radius_end_mm = 0.0;  // table turning feed moves
  bool cutting = false;

  DrillCycle drill;
  TableSpin spin;
  ProbeMove probe;
  double spindle_rpm = 0.0;
  bool spindle_clockwise = true;
  int tool_index = -1;          // into IrProgram::tools (kToolChange, kOperationStart)
  double dwell_s = 0.0;
  int work_offset = 1;
  std::string text;             // kOperationStart: "OP 2 holes: ..."

  // Source in the test piece: operation number (1-based), pass and move indices (0-based),
  // -1 when the instruction is added by the post (spindle, coolant, initial moves).
  int op = 0, pass = -1, move = -1;
};

struct IrTool {
  testpieces::Tool tool;   // as the test piece defines it
  int number = 0;          // posted T number
  double length_mm = 0.0;  // gauge length in the tool table
};

struct IrProgram {
  std::string piece_name;
  std::string instrument;      // measuring program: what it measures ("" for a test piece)
  testpieces::PieceKind kind = testpieces::PieceKind::kTurning;
  std::string standard;        // the clause the program implements
  std::string machine_name;
  kinematics::MachineModel machine;  // nominal planning machine (TCP coordinates, checks)
  bool has_a = false, has_b = false, has_c = false;  // rotary words the machine takes
  std::vector<IrTool> tools;
  std::vector<std::string> operation_names;  // index op - 1
  std::vector<Instr> instrs;
  double safe_z_mm = 0.0;      // machine Z of the first (safe) position
  // Bounding box of the stock in the part frame (Heidenhain BLK FORM); set by PostProgram.
  Eigen::Vector3d stock_min_mm = Eigen::Vector3d::Zero(), stock_max_mm = Eigen::Vector3d::Zero();
  double duration_s = 0.0;
  bool uses_table_turning = false;
  bool uses_five_axis = false;
  bool uses_rotary = false;
};

// Builds the IR of `piece` (its operations, in order). Drill cycles are recognised in reamer
// passes (rapid to R, feed to the bottom, feed back to R); zero-length rapids are dropped.
// Errors: options invalid, tool numbers that collide after ToolSetting remapping.
Result<IrProgram> BuildIr(const testpieces::TestPiece& piece, const GcodeOptions& options);

// The clause of the standard / paper a piece kind implements (header line).
std::string StandardClause(testpieces::PieceKind kind);

// Rotary-only change / five-axis test (1e-12 rad, 1e-9 mm).
bool LinearAxesEqual(const kinematics::AxisState& a, const kinematics::AxisState& b);
bool RotaryAxesEqual(const kinematics::AxisState& a, const kinematics::AxisState& b);

}  // namespace tpcal::gcode
