// The stage of `tpcal plan --instrument datum_ball`: the plan of a datum-ball test
// (testpieces/datum_ball_plan.h) as a `tpcal ballpos v1` file holding the NOMINAL centring
// commands (what an error-free machine reads; docs/formats/ballpos.md, "Plans"), and optionally
// the NC program that probes the ball at every position (gcode/datum_ball_program.h) in one of
// the four dialects, with the LinuxCNC tool table. Nothing is parsed from the command line here
// and nothing is written: the caller writes `files`.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/status.h"
#include "gcode/datum_ball_program.h"
#include "pipeline/gcode_stage.h"
#include "testpieces/datum_ball_plan.h"

namespace tpcal::pipeline {

struct DatumBallPlanRequest {
  std::string machine_path;                // tpcal.machine/1; "" = the nominal bc_table
  std::vector<double> tilt_deg;            // empty = seed 001's 0, +30, -30 deg
  std::optional<double> c_step_deg;        // unset = 30 deg
  std::vector<double> ball_part_mm;        // empty = (200, 0.1, 300) mm; else x, y, z (part frame)
  std::optional<double> ball_diameter_mm;  // unset = 25 mm
  std::string csv_path;                    // -o: the ballpos plan
  // The NC program: nc.output "" = none; nc.dialect "" = from the output's extension (.nc fanuc,
  // .ngc linuxcnc, .mpf sinumerik, .h heidenhain); nc.post_path, nc.date as for `tpcal gcode`.
  GcodeRequest nc;
  gcode::DatumBallProbeOptions probe;
};

struct DatumBallPlanResult {
  testpieces::DatumBallPlan plan;
  std::string machine;                          // the machine's name (or type)
  std::vector<Eigen::Vector3d> centre_commands_mm;  // nominal centring commands, per position
  std::string csv;                              // the ballpos plan's text
  std::optional<gcode::PostedInstrumentProgram> posted;  // when nc.output is set
  gcode::GcodeOptions options;                  // the post options used (when posted)
  std::vector<GcodeFile> files;                 // the plan, then the program and its tool table
};

// Errors (exit 2 in the CLI, nothing written), in this order: machine file (file:line); options
// ("tpcal plan: --ball: expected x,y,z", "--c-step-deg: ...", "--tilt-deg: ...", "--dialect: ..."),
// the plan's (a tilt outside the stroke), the post options (--post file:line), the program's
// checks ("PROGRAM: N120: rapid target outside the machine's travel"), an output directory that
// is missing or read-only.
Result<DatumBallPlanResult> RunDatumBallPlanStage(const DatumBallPlanRequest& request);

// The ballpos plan text: `# tpcal ballpos v1`, `# units: mm`, the plan comment, the header
// (<tilt>_deg, C_deg, x, y, z) and one row per position, 4 decimals (0.1 um).
std::string FormatBallPositionPlan(const testpieces::DatumBallPlan& plan,
                                   const std::vector<Eigen::Vector3d>& centre_commands_mm,
                                   const std::string& machine);

}  // namespace tpcal::pipeline
