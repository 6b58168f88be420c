// The NC program of a datum-ball test (seed 001; as Heidenhain KinematicsOpt cycle 451, Siemens
// CYCLE996, Renishaw AxiSet): at each rotary position of the plan the spindle touch probe touches
// the ball five times (from above along -Z, then from +X, -X, +Y, -Y at the height of the nominal
// centre), with a retract after every touch, a safe Z above the ball's whole sweep while the
// rotary axes index, and a comment block naming each position. Built as the one IR (gcode/ir.h,
// InstrKind::kProbe) and posted by the dialect posts (gcode/post.h); choices in DIALECTS.md.
//
// Geometry (nominal machine, machine frame, mm): the centring command c of a position is
// kinematics::BallCentreCommand with zero errors; a linear command moves the tool relative to the
// ball along the machine axes, so the stylus centre touches the sphere at c + (R + r) d for the
// outward direction d (R ball radius, r stylus radius). Each touch starts at c + (R + r + approach)
// d and is programmed to c + (R + r - overtravel) d.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/status.h"
#include "gcode/ir.h"
#include "gcode/options.h"
#include "gcode/post.h"
#include "gcode/posted_instrument_program.h"
#include "kinematics/machine_model.h"
#include "testpieces/datum_ball_plan.h"

namespace tpcal::gcode {

struct DatumBallProbeOptions {
  double stylus_diameter_mm = 6.0;       // stylus ball of the touch probe
  double probe_length_mm = 0.0;          // gauge length in the tool table; 0: default_tool_length_mm
  int probe_tool_number = 1;             // posted T number of the probe
  double approach_mm = 5.0;              // gap between stylus and ball where each touch starts
  double overtravel_mm = 2.0;            // programmed probe target beyond the nominal contact
  double probe_feed_mm_per_min = 200.0;  // touch feed
  double safe_clearance_mm = 50.0;       // safe Z: this above the highest stylus-on-ball-top Z over
                                         // all positions and the index sweeps between them
  // Time estimate only (header line): rapid traverse and rotary index rates.
  double rapid_mm_per_min = 10000.0;
  double index_deg_per_min = 3600.0;
  Status Validate() const;  // kInvalidArgument naming the option
};

// The IR: work offset, probe tool change, safe Z, then per position a comment (op = position,
// 1-based), the rotary index at safe Z, the five touches, the retract to safe Z; program end.
// Errors: invalid options, a position the nominal machine cannot centre (kNotConverged).
Result<IrProgram> BuildDatumBallIr(const testpieces::DatumBallPlan& plan, const kinematics::MachineModel& machine,
                                   const DatumBallProbeOptions& probe, const GcodeOptions& options);

// Builds the IR, posts it in options.dialect, checks every target against the machine's strokes
// (options.safety.check_strokes; the error names the block) and the dialect whitelist
// (gcode/dialect_check.h). Errors: those of BuildDatumBallIr, PostIr, the checks.
Result<PostedInstrumentProgram> PostDatumBallProgram(const testpieces::DatumBallPlan& plan,
                                                     const kinematics::MachineModel& machine,
                                                     const DatumBallProbeOptions& probe, const GcodeOptions& options);

}  // namespace tpcal::gcode
