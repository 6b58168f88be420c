// The stage of `tpcal plan --instrument ballbar`: the plan of a double-ball-bar test (seed 003; ISO
// 230-4 circular tests) as a `tpcal ballbar v1` file holding the NOMINAL readings (dl_um 0: what an
// error-free machine reads; docs/formats/ballbar.md, "Plans"), one row per reading to take, and
// optionally the NC program of the test (gcode/ballbar_program.h) in one of the four dialects, with
// the LinuxCNC tool table. Nothing is parsed from the command line here and nothing is written:
// the caller writes `files`.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/status.h"
#include "gcode/ballbar_program.h"
#include "kinematics/ballbar_setup.h"
#include "kinematics/machine_model.h"
#include "pipeline/gcode_stage.h"
#include "pipeline/io/ballbar_io.h"

namespace tpcal::pipeline {

// The angles of every installation (deg). Defaults (seed 003): a C axis 0 to
// 360 every 20 deg; a tilt axis (A, B) 0 to -100 every 5 deg; a circle's path angle 0 to 359 every
// 1 deg, read counter-clockwise then clockwise. `step_deg` replaces the default step (the same
// ranges); `angles_deg` gives the list for every installation.
struct BallbarAngles {
  std::vector<double> angles_deg;
  std::optional<double> step_deg;
  // kInvalidArgument ("--step-deg: ...", "--angles-deg: ...") at "tpcal plan" / "tpcal simulate":
  // a step outside (0, 360], both given, an angle that is not finite, repeated angles.
  Status Validate(const std::string& command) const;
};

// The installations of `setup` on `model` with their angles in test order. Errors: the angles'
// (Validate), an installation the machine cannot hold (kInvalidArgument located at `setup_path`).
Result<std::vector<gcode::BallbarProgramTest>> MakeBallbarTests(const kinematics::MachineModel& model,
                                                                const kinematics::BallbarSetup& setup,
                                                                const BallbarAngles& angles,
                                                                const std::string& setup_path,
                                                                const std::string& command);

// The readings of `tests`, dl_um 0, in test order. With a circle among them the file has the
// direction column: a circle's angles counter-clockwise, then the same angles in reverse order
// clockwise; a rotary row names the sense its axis turns to reach it (ccw: increasing command;
// the first row as the second).
BallbarFile BallbarPlanReadings(const std::vector<gcode::BallbarProgramTest>& tests);

struct BallbarPlanRequest {
  std::string setup_path;    // tpcal.ballbar_setup/1 (required)
  std::string machine_path;  // tpcal.machine/1; "" = the nominal bhead_ctable
  BallbarAngles angles;
  std::string csv_path;      // -o: the ballbar plan
  // The NC program: nc.output "" = none; nc.dialect "" = from the output's extension (.nc fanuc,
  // .ngc linuxcnc, .mpf sinumerik, .h heidenhain); nc.post_path, nc.date as for `tpcal gcode`.
  GcodeRequest nc;
  gcode::BallbarProgramOptions program;
};

struct BallbarPlanResult {
  kinematics::BallbarSetup setup;
  std::string machine;                        // the machine's name (or type)
  std::vector<gcode::BallbarProgramTest> tests;
  BallbarFile readings;                       // the plan's rows (dl_um 0)
  std::string csv;                            // FormatBallbarPlan
  std::optional<gcode::PostedInstrumentProgram> posted;  // when nc.output is set
  gcode::GcodeOptions options;                // the post options used (when posted)
  std::vector<GcodeFile> files;               // the plan, then the program and its tool table
};

// Errors (exit 2 in the CLI, nothing written), in this order: no --setup; machine and set-up files
// (file:line); a circle feed <= 0 (--feed-mm-per-min); the angles (--step-deg, --angles-deg); an installation the machine cannot hold
// (at the set-up file); --dialect / --post without --nc, a dialect the program's extension does
// not name; the post options (--post file:line); the program's (a stroke violation names the
// block, located at the program's path); an output directory that is missing or read-only.
Result<BallbarPlanResult> RunBallbarPlanStage(const BallbarPlanRequest& request);

// The plan text: FormatBallbar(readings) with a comment line after `# units: mm` saying it is the
// plan of an error-free `machine`.
std::string FormatBallbarPlan(const BallbarFile& readings, const std::string& machine);

}  // namespace tpcal::pipeline
