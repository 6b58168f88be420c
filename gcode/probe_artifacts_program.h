// The NC program of an on-machine probing test of artifacts (seed 000): at each indexed rotary
// pose of the plan (testpieces/probe_artifacts_plan.h) the spindle touch probe touches every
// planned face once, at the face centre, along the face's inward normal. Built as the one IR
// (gcode/ir.h, InstrKind::kProbe) and posted by the dialect posts (gcode/post.h), as the
// datum-ball program (gcode/datum_ball_program.h); choices in DIALECTS.md.
//
// Geometry (nominal machine, machine frame, mm; the stylus vertical). A linear command places
// the stylus-ball centre (the tool reference point). For a planned touch with contact c, approach
// d (unit, toward the face; n = -d the outward normal) and stylus radius r (the plan's
// probe_radius_mm), the ball centre at the touch is c + r n; each touch starts at
// s = c + (r + approach_mm) n and is programmed to c + (r - overtravel_mm) n.
//
// Moves. Work offset, probe tool change, safe Z; per pose a comment (op = pose, 1-based, naming
// A, C and the touches in order, Heidenhain result numbers Q1..Qk: "Q1..: 1+X 1-X ...", cut with
// "..." at 200 characters) and, if the pose has
// a touch, the rotary index at safe Z; per touch: rapid X Y at safe Z over s, rapid Z down to s,
// the probe move, rapid back to s, rapid Z up to safe Z; program end. These are the corridors the
// plan checked (from clearance_mm off the face and straight up), so approach_mm must not exceed
// the plan's clearance_mm (not stored in the plan: the caller's to keep; both defaults fit,
// 5 <= 10 mm). Safe Z: `safe_clearance_mm` above the highest of (every box corner over the poses
// and the index sweeps between them, sampled every degree, + r) and every start point.
//
// Heidenhain posts a touch along one machine axis with touch-probe cycle 0 (result Q<n>) and an
// oblique one (a C that is not a multiple of 90 deg, a tilted A other than -90 deg) with cycle 4
// MEASURING IN 3-D (results Q(30 + 3 (n - 1))..+2); the G-code dialects post any direction.
#pragma once

#include <string>

#include "core/status.h"
#include "gcode/ir.h"
#include "gcode/options.h"
#include "gcode/post.h"
#include "gcode/posted_instrument_program.h"
#include "kinematics/machine_model.h"
#include "testpieces/probe_artifacts_plan.h"

namespace tpcal::gcode {

struct ProbeArtifactsProbeOptions {
  double probe_length_mm = 0.0;          // gauge length in the tool table; 0: default_tool_length_mm
  int probe_tool_number = 1;             // posted T number of the probe
  double approach_mm = 5.0;              // gap between stylus ball and face where each touch starts
                                         // (<= the plan's clearance_mm)
  double overtravel_mm = 2.0;            // programmed probe target beyond the nominal contact
  double probe_feed_mm_per_min = 200.0;  // touch feed
  double safe_clearance_mm = 50.0;       // safe Z: this above the highest box corner + r over all
                                         // poses and the index sweeps between them
  // Time estimate only (header line): rapid traverse and rotary index rates.
  double rapid_mm_per_min = 10000.0;
  double index_deg_per_min = 3600.0;
  Status Validate() const;  // kInvalidArgument naming the option
};

// The IR (moves above). The probe is a ToolKind::kTouchProbe of diameter 2 r. Errors: invalid
// options (kInvalidArgument), a plan with no pose, no touch, a stylus radius <= 0, a touch
// naming an artifact the plan does not hold or at a rotary position that is not one of the
// plan's poses (compared exactly; kInvalidArgument).
Result<IrProgram> BuildProbeArtifactsIr(const testpieces::ProbeArtifactsPlan& plan,
                                        const kinematics::MachineModel& machine,
                                        const ProbeArtifactsProbeOptions& probe, const GcodeOptions& options);

// Builds the IR, posts it in options.dialect, checks every target against the machine's strokes
// (options.safety.check_strokes; the error names the block) and the dialect whitelist
// (gcode/dialect_check.h). Errors: those of BuildProbeArtifactsIr, PostIr (Heidenhain: an oblique
// touch numbered beyond 23 within its pose), the checks.
Result<PostedInstrumentProgram> PostProbeArtifactsProgram(const testpieces::ProbeArtifactsPlan& plan,
                                                          const kinematics::MachineModel& machine,
                                                          const ProbeArtifactsProbeOptions& probe,
                                                          const GcodeOptions& options);

}  // namespace tpcal::gcode
