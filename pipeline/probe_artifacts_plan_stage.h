// The stage of `tpcal plan --instrument probe_artifacts`: the plan of an on-machine probing test
// of artifacts (seed 000; testpieces/probe_artifacts_plan.h) as a `tpcal probepts v1` file
// holding the NOMINAL contact points and approach directions (what an error-free machine reports;
// docs/formats/probepts.md, "Plans"), the touches the plan left out with their reason, and
// optionally the NC program that probes every planned face (gcode/probe_artifacts_program.h) in
// one of the four dialects, with the LinuxCNC tool table. Nothing is parsed from the command line
// here and nothing is written: the caller writes `files`.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/status.h"
#include "gcode/probe_artifacts_program.h"
#include "kinematics/probe_artifacts.h"
#include "pipeline/gcode_stage.h"
#include "pipeline/io/probepts_io.h"
#include "testpieces/probe_artifacts_plan.h"

namespace tpcal::pipeline {

struct ProbeArtifactsPlanRequest {
  std::string machine_path;    // tpcal.machine/1 (an A/C table); "" = the nominal ac_table
  std::string artifacts_path;  // tpcal.artifacts/1; "" = kinematics::Seed000Artifacts()
  std::string csv_path;        // -o: the probepts plan
  // Seed 000's pattern by default: A 0, -30, -60, -90 deg, C every 60 deg, stylus radius 3 mm.
  testpieces::ProbeArtifactsPlanOptions plan;
  // The NC program: nc.output "" = none; nc.dialect "" = from the output's extension (.nc fanuc,
  // .ngc linuxcnc, .mpf sinumerik, .h heidenhain); nc.post_path, nc.date as for `tpcal gcode`.
  GcodeRequest nc;
  gcode::ProbeArtifactsProbeOptions probe;
};

struct ProbeArtifactsPlanResult {
  testpieces::ProbeArtifactsPlan plan;
  std::string machine;       // the machine's name (or type)
  ProbePointFile points;     // the plan's rows (is_plan), one per planned touch
  std::string csv;           // FormatProbePoints(points)
  std::vector<std::string> skipped_lines;  // SkippedTouchLine of every skipped touch, in plan order
  std::optional<gcode::PostedInstrumentProgram> posted;  // when nc.output is set
  gcode::GcodeOptions options;                        // the post options used (when posted)
  std::vector<GcodeFile> files;                       // the plan, then the program and its tool table
};

// Errors (exit 2 in the CLI, nothing written), in this order: machine file, artifacts file
// (file:line); the plan's (kInvalidArgument: not an A/C table, an A outside the stroke, a bad
// option; located at the machine file or "tpcal plan"); --dialect / --post without --nc, a
// dialect the program's extension does not name; the post options (--post file:line); the
// program's (Heidenhain refuses oblique approaches; a stroke violation names the block, located
// at the program's path); an output directory that is missing or read-only.
Result<ProbeArtifactsPlanResult> RunProbeArtifactsPlanStage(const ProbeArtifactsPlanRequest& request);

// The plan as probepts rows: columns A_deg, C_deg (rounded to 1e-9 deg, so 60 reads "60"), the
// artifact's name (its 1-based index when the name is empty), the face, the nominal contact
// (machine frame, mm, rounded to 1e-4 mm = 0.1 um) and the approach (unit, rounded to 1e-12);
// is_plan set.
ProbePointFile ProbeArtifactsPlanPoints(const testpieces::ProbeArtifactsPlan& plan);

// One line per skipped touch: "A -90 C 60: artifact 1 face -X skipped: faces down".
std::string SkippedTouchLine(const testpieces::ProbeArtifactsPlan& plan, const testpieces::SkippedTouch& skipped);

// The artifact's name in the files (its 1-based index when the name is empty).
std::string ArtifactLabel(const kinematics::ArtifactSet& artifacts, int index);

// A rotary command in the files, degrees rounded to 1e-9 deg ("-30", "60"; never "-0").
double ProbeRotaryDeg(double rad);

}  // namespace tpcal::pipeline
