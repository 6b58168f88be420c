// Post-processor options: the dialect, the program identity and the settings of one machine's
// control that the test piece does not fix (work offset, coolant, block numbering, number format,
// C axis as a turning spindle, five-axis mode, tool numbers and lengths, safety checks, backplot).
// Tools, feeds, speeds, sizes and stock live in the test piece (testpieces::PieceConfig): a
// dimension is written once. YAML: gcode/options_yaml.h. Dialect choices: gcode/DIALECTS.md.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/status.h"

namespace tpcal::gcode {

enum class Dialect {
  kFanuc,       // ISO / Fanuc 0i-F / 30i (M series), .nc
  kLinuxCnc,    // LinuxCNC RS274NGC, .ngc (+ tool table .tbl)
  kSinumerik,   // Siemens Sinumerik 840D sl, .mpf
  kHeidenhain,  // Heidenhain TNC 640 Klartext, .h
};
const char* DialectName(Dialect d);                      // "fanuc", "linuxcnc", "sinumerik", "heidenhain"
std::optional<Dialect> DialectFromName(std::string_view name);
const char* DialectTitle(Dialect d);                     // "ISO / Fanuc (M series)", ...
const char* ProgramExtension(Dialect d);                 // ".nc", ".ngc", ".mpf", ".h"

enum class Coolant { kOff, kFlood, kMist };              // M9 / M8 / M7
const char* CoolantName(Coolant c);                      // "off", "flood", "mist"

// Simultaneous five-axis moves (the cone frustum): axis commands with inverse-time feed, or tool
// centre point control (Fanuc G43.4, Sinumerik TRAORI, Heidenhain M128) with X, Y, Z the tool tip
// in the part frame. LinuxCNC (trivial kinematics in rs274) supports only kJointInverseTime.
enum class FiveAxisMode { kJointInverseTime, kToolCenterPoint };
const char* FiveAxisModeName(FiveAxisMode m);            // "joint_inverse_time", "tcp"

// The C table as a turning spindle (seed 002 table turning). Machine-builder specific: every code
// here must be checked against the machine's manual. Defaults per dialect: ForDialect().
struct CSpindleOptions {
  // M-code that switches the C axis to spindle mode before turning and back after (-1: none).
  // Fanuc: builder M-code; Sinumerik: none (M<n>=3 switches, M<n>=70 returns to axis mode);
  // Heidenhain: none (FUNCTION MODE TURN / MILL); LinuxCNC: unused (M64 / M65 P<bit>).
  int mode_on_mcode = -1;
  int mode_off_mcode = -1;
  int spindle_number = 2;          // Sinumerik: SETMS(n), M<n>=...; Fanuc, Heidenhain: unused
  bool css = true;                 // constant surface speed (G96 / VCONST:ON) on the C spindle;
                                   // false: constant rpm at the pass's largest cutting radius
  double max_rpm = 0.0;            // table speed clamp (rpm); 0: the test piece's own clamp;
                                   // otherwise the smaller of the two
  int orient_mcode = 19;           // orients and holds the tool spindle (turning insert edge)
  double orient_angle_deg = 0.0;   // tool spindle angle during turning
  int positive_c_mcode = 3;        // spindle M-code (3 or 4) that turns the table in +C (ISO 841)
  int heidenhain_start_mcode = 303;// Heidenhain turning spindle start for +C (the other: +1)
  bool heidenhain_x_diameter = true;  // Heidenhain FUNCTION MODE TURN: X written as a diameter
  // LinuxCNC: motion.digital-out-<bit> switches the C drive to spindle mode (M64 / M65),
  // motion.analog-out-<channel> carries the signed table speed in rpm (M68 immediate, M67
  // synchronised with the next move). LinuxCNC's G96 acts on spindle 0 and the X radius only,
  // so constant surface speed is posted as constant-rpm segments of at most css_step_mm radius
  // change each, the feed per minute = feed per rev x segment rpm.
  int linuxcnc_mode_bit = 0;
  int linuxcnc_speed_channel = 0;
  double css_step_mm = 2.0;
  Status Validate() const;  // kInvalidArgument naming the c_spindle.* key
};

// Posted tool number and length of one test-piece tool (matched by the piece's T number).
struct ToolSetting {
  int piece_tool = 0;      // testpieces::Tool::number
  int number = 0;          // T number / pocket in the posted program (0: same as piece_tool)
  double length_mm = 0.0;  // gauge length (tool table Z offset); 0: the piece's gauge length,
                           // or default_tool_length_mm when the piece has none
};

// Checks run on the program before it is returned (gcode/safety.h).
struct SafetyOptions {
  bool check_strokes = true;        // every target inside the machine's strokes
  bool check_rapids = true;         // no rapid enters the stock envelope (below the safe height)
  bool check_tool_fit = true;       // reamer = hole, end mill radius <= groove width / 2, ...
  double rapid_tolerance_mm = 0.01; // a rapid whose tool enters the envelope deeper than this is
                                    // a violation (0: touching a finished face is allowed)
  double rapid_sample_mm = 1.0;     // rapid paths sampled every this (linear) / degree (rotary)
  double tool_fit_tol_mm = 0.001;   // reamer diameter vs hole diameter
  Status Validate() const;
};

struct BackplotOptions {
  double width_px = 1200.0;         // whole drawing, two views side by side
  double arc_segment_deg = 2.0;     // arcs not in the view plane are drawn as polylines
  Status Validate() const;
};

struct GcodeOptions {
  Dialect dialect = Dialect::kLinuxCnc;
  std::string program_name = "TPCAL";    // file stem, Heidenhain PGM / Sinumerik MPF name:
                                         // [A-Z0-9_], starts with a letter
  int program_number = 1000;             // Fanuc O-number (1..9999)
  std::string tool_table_file;           // LinuxCNC tool table file name named in the header and
                                         // PostedProgram; "": "<program_name>.tbl". Not a YAML
                                         // key: the CLI sets it ("PROGRAM.tbl" beside -o PROGRAM)
  std::string date;                      // header date "YYYY-MM-DD"; empty: "not recorded"
                                         // (golden files); the CLI passes today's date
  std::string generator = "tpcal";       // header "generated by" (the CLI adds its version)
  int work_offset = 1;                   // 1..6: G54..G59 / Heidenhain preset 1..6
  Coolant coolant = Coolant::kFlood;     // seed 002 sec. 4.1: emulsion
  int block_start = 10;                  // first N number
  int block_step = 10;                   // N increment; 0: no N numbers (not for Heidenhain,
                                         // which numbers every line)
  int linear_decimals = 4;               // mm (4: Fanuc IS-C, 0.1 um)
  int rotary_decimals = 4;               // deg
  double default_tool_length_mm = 100.0; // tool table length when neither ToolSetting nor the
                                         // piece gives one
  std::vector<ToolSetting> tools;
  CSpindleOptions c_spindle;
  FiveAxisMode five_axis = FiveAxisMode::kJointInverseTime;
  SafetyOptions safety;
  BackplotOptions backplot;

  // Defaults for a dialect (C spindle codes, five-axis mode): see DIALECTS.md.
  static GcodeOptions ForDialect(Dialect d);
  // kInvalidArgument naming the YAML key.
  Status Validate() const;
  // The posted T number of a piece tool, and its length.
  int PostedToolNumber(int piece_tool) const;
  const ToolSetting* FindTool(int piece_tool) const;
};

}  // namespace tpcal::gcode
