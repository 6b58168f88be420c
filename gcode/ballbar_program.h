// The NC program of a double-ball-bar test (seed 003, Ni et al.; ISO 230-4 circular tests): the
// installations of a set-up (kinematics/ballbar_setup.h) one after the other, each with the bar
// mounted by the operator at a program stop (M0) and removed at another. Built as the one IR
// (gcode/ir.h) and posted by the dialect posts (gcode/post.h), as the probing programs
// (gcode/datum_ball_program.h); choices in DIALECTS.md.
//
// Commands are those of kinematics::BallbarCommand on the nominal machine (the tool reference point
// carries the spindle-side ball, offset by tool_ball_in_tool_mm). Per installation: a comment, the
// rotary axes indexed at safe Z to the start, rapid X Y over the start, rapid Z down to approach_mm
// above it, feed down, M0 "mount the bar", then
//   rotary kinds: a dwell of dwell_s at every angle of the test (one reading each), and between two
//     angles feed moves of at most max_step_deg of the turned axis with every axis at
//     BallbarCommand (the tool ball follows the workpiece ball; a linear interpolation of the axes
//     over a step of s deg leaves the bar off its length by about r (1 - cos(s / 2)), r the tool
//     ball's distance from the turned axis: 0.01 mm at r = 250 mm, s = 1 deg), inverse time
//     (G93) at rotary_feed_deg_per_min, or F in deg/min when the linear axes stay;
//   circle (ISO 230-4): the tool ball starts feed_in_mm inside the circle; a feed-in arc of
//     feed_arc_deg (radius feed_in_mm / (1 - cos feed_arc_deg)) joins the circle tangentially at
//     path angle 0, the full circle counter-clockwise (G03 / DR+), a feed-out arc continuing the
//     feed-in circle; a dwell; the same clockwise (G02 / DR-) back to the start. Arcs in the
//     installation's plane: G17 XY, G18 ZX, G19 YZ (the path angle's positive sense is G03's).
// then M0 "remove the bar", feed up approach_mm, rapid to safe Z. Safe Z: safe_clearance_mm above
// the highest tool reference point Z of the whole test.
#pragma once

#include <string>
#include <vector>

#include "core/status.h"
#include "gcode/ir.h"
#include "gcode/options.h"
#include "gcode/post.h"
#include "gcode/posted_instrument_program.h"
#include "kinematics/ballbar.h"
#include "kinematics/machine_model.h"

namespace tpcal::gcode {

struct BallbarProgramOptions {
  double feed_mm_per_min = 1000.0;         // circle: contouring feed of the test
  double feed_in_mm = 1.5;                 // circle: the start this far inside the circle (bar short)
  double feed_arc_deg = 180.0;             // circle: feed-in and feed-out arcs, in (0, 180] deg
  double rotary_feed_deg_per_min = 360.0;  // rotary kinds: speed of the turned axis between readings
  double max_step_deg = 1.0;               // rotary kinds: largest step of one feed move, deg
  double dwell_s = 2.0;                    // rotary kinds: at each reading; circle: between directions
  double approach_mm = 10.0;               // feed distance above the start (bar not mounted)
  double approach_feed_mm_per_min = 500.0;
  double safe_clearance_mm = 50.0;
  double tool_ball_diameter_mm = 12.7;     // tool table entry of the spindle-side cup
  double tool_length_mm = 0.0;             // gauge length to the ball centre; 0: default_tool_length_mm
  int tool_number = 1;
  double rapid_mm_per_min = 10000.0;       // time estimate only (header line)
  double index_deg_per_min = 3600.0;
  Status Validate() const;                 // kInvalidArgument naming the option
};

// One installation of the program and, for a rotary kind, its angles in test order (deg; a
// circle's readings come from the continuous path, its angles are not used here).
struct BallbarProgramTest {
  kinematics::BallbarGeometry geometry;
  std::vector<double> angles_deg;
};

// The IR (above). Errors: invalid options; no test; a rotary test with no angle; the commands'
// (kNotConverged naming the installation and angle).
Result<IrProgram> BuildBallbarIr(const std::vector<BallbarProgramTest>& tests, const kinematics::MachineModel& machine,
                                 const BallbarProgramOptions& bar, const GcodeOptions& options);

// Builds the IR, posts it in options.dialect, checks every target (arcs every 5 deg) against the
// machine's strokes (options.safety.check_strokes; the error names the block) and the dialect
// whitelist (gcode/dialect_check.h). Errors: those of BuildBallbarIr, PostIr, the checks.
Result<PostedInstrumentProgram> PostBallbarProgram(const std::vector<BallbarProgramTest>& tests,
                                                   const kinematics::MachineModel& machine,
                                                   const BallbarProgramOptions& bar, const GcodeOptions& options);

}  // namespace tpcal::gcode
