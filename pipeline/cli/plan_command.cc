// tpcal plan --testpiece NAME [--config TP.yaml] [--machine M.yaml] [--density paper|dense|N]
//            [--levels N] -o PLAN.csv [--step PIECE.step] [--write-config TP_OUT.yaml]
// tpcal plan --instrument datum_ball [--machine M.yaml] [--tilt-deg 0,30,-30] [--c-step-deg 30]
//            [--ball X,Y,Z] [--ball-diameter D] -o PLAN.csv [--nc PROGRAM [--dialect D] [--post P.yaml]
//            [--date YYYY-MM-DD|none]]
// tpcal plan --instrument probe_artifacts [--machine M.yaml] [--artifacts A.yaml] [--tilt-deg 0,-30,-60,-90]
//            [--c-step-deg 60] [--probe-radius-mm 3] -o PLAN.csv [--nc PROGRAM [--dialect D] [--post P.yaml]
//            [--date YYYY-MM-DD|none]]
// tpcal plan --instrument ballbar --setup S.yaml [--machine M.yaml] [--angles-deg A,... | --step-deg D]
//            -o PLAN.csv [--nc PROGRAM [--dialect D] [--post P.yaml] [--date YYYY-MM-DD|none]
//            [--feed-mm-per-min 1000]]
//
// Writes the CMM probing plan of a test piece as the `tpcal plan v1` CSV (docs/formats/probing_plan.md):
// nominal points and outward normals in the part's DATUM frame, then op, t_s, the
// rotary axes (A_deg/B_deg, C_deg: those the machine has), X_mm, Y_mm, Z_mm of the machine
// state that cut each point (pipeline/plan_stage.h). The instruments: pipeline/datum_ball_plan_stage.h
// (tpcal ballpos v1), pipeline/probe_artifacts_plan_stage.h (tpcal probepts v1),
// pipeline/ballbar_plan_stage.h (tpcal ballbar v1).
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "pipeline/cli/commands.h"
#include "pipeline/ballbar_plan_stage.h"
#include "pipeline/cli/piece_args.h"
#include "pipeline/datum_ball_plan_stage.h"
#include "pipeline/io/atomic_file.h"
#include "pipeline/plan_stage.h"
#include "pipeline/probe_artifacts_plan_stage.h"
#include "testpieces/brep.h"
#include "testpieces/dmis_program.h"

namespace tpcal::cli {
namespace {

struct PlanArgs {
  PieceArgs piece;
  std::string out;
  std::string step;
  std::string write_config;
  std::string dmis;
  std::string instrument;  // "" = a test piece; datum_ball; probe_artifacts
  // --tilt-deg, --c-step-deg, --nc, --dialect, --post, --date land here for both instruments.
  pipeline::DatumBallPlanRequest ball;
  std::string artifacts;                  // probe_artifacts: --artifacts
  std::optional<double> probe_radius_mm;  // probe_artifacts: --probe-radius-mm
  std::string setup;                      // ballbar: --setup
  pipeline::BallbarAngles bar_angles;     // ballbar: --angles-deg, --step-deg
  std::optional<double> bar_feed_mm_per_min;  // ballbar: --feed-mm-per-min
};

Status PlanUsageError(const std::string& message) { return Status(StatusCode::kInvalidArgument, message, "tpcal plan"); }

// The options of one mode used in the other are errors, not silently ignored.
Status CheckPlanMode(const PlanArgs& a) {
  const pipeline::DatumBallPlanRequest& b = a.ball;
  if (a.instrument.empty()) {
    if (a.piece.testpiece.empty())
      return PlanUsageError("--testpiece NAME (or --instrument datum_ball, probe_artifacts or ballbar) is required");
    for (const auto& [name, set] : std::vector<std::pair<std::string, bool>>{
             {"--tilt-deg", !b.tilt_deg.empty()}, {"--c-step-deg", b.c_step_deg.has_value()},
             {"--nc", !b.nc.output.empty()}, {"--dialect", !b.nc.dialect.empty()}, {"--post", !b.nc.post_path.empty()},
             {"--date", !b.nc.date.empty()}}) {
      const bool every_instrument = name != "--tilt-deg" && name != "--c-step-deg";  // the --nc options
      if (set)
        return PlanUsageError(name + (every_instrument ? " needs --instrument datum_ball, probe_artifacts or ballbar"
                                                       : " needs --instrument datum_ball or probe_artifacts"));
    }
    if (!b.ball_part_mm.empty()) return PlanUsageError("--ball needs --instrument datum_ball");
    if (b.ball_diameter_mm) return PlanUsageError("--ball-diameter needs --instrument datum_ball");
    if (!a.artifacts.empty()) return PlanUsageError("--artifacts needs --instrument probe_artifacts");
    if (a.probe_radius_mm) return PlanUsageError("--probe-radius-mm needs --instrument probe_artifacts");
    if (!a.setup.empty()) return PlanUsageError("--setup needs --instrument ballbar");
    if (!a.bar_angles.angles_deg.empty()) return PlanUsageError("--angles-deg needs --instrument ballbar");
    if (a.bar_angles.step_deg) return PlanUsageError("--step-deg needs --instrument ballbar");
    if (a.bar_feed_mm_per_min) return PlanUsageError("--feed-mm-per-min needs --instrument ballbar");
    return Status::Ok();
  }
  for (const auto& [name, set] : std::vector<std::pair<std::string, bool>>{
           {"--testpiece", !a.piece.testpiece.empty()}, {"--config", !a.piece.config.empty()},
           {"--density", !a.piece.density.empty()}, {"--levels", a.piece.levels.has_value()},
           {"--step", !a.step.empty()}, {"--write-config", !a.write_config.empty()}, {"--dmis", !a.dmis.empty()}}) {
    if (set) return PlanUsageError(name + " is for test pieces, not --instrument " + a.instrument);
  }
  if (a.instrument != "ballbar") {
    if (!a.setup.empty()) return PlanUsageError("--setup is for --instrument ballbar, not " + a.instrument);
    if (!a.bar_angles.angles_deg.empty())
      return PlanUsageError("--angles-deg is for --instrument ballbar, not " + a.instrument);
    if (a.bar_angles.step_deg) return PlanUsageError("--step-deg is for --instrument ballbar, not " + a.instrument);
    if (a.bar_feed_mm_per_min)
      return PlanUsageError("--feed-mm-per-min is for --instrument ballbar, not " + a.instrument);
  } else {
    if (!b.tilt_deg.empty()) return PlanUsageError("--tilt-deg is not an option of --instrument ballbar");
    if (b.c_step_deg) return PlanUsageError("--c-step-deg is not an option of --instrument ballbar (--step-deg)");
    if (!b.ball_part_mm.empty()) return PlanUsageError("--ball is for --instrument datum_ball, not ballbar");
    if (b.ball_diameter_mm) return PlanUsageError("--ball-diameter is for --instrument datum_ball, not ballbar");
    if (!a.artifacts.empty()) return PlanUsageError("--artifacts is for --instrument probe_artifacts, not ballbar");
    if (a.probe_radius_mm) return PlanUsageError("--probe-radius-mm is for --instrument probe_artifacts, not ballbar");
    return Status::Ok();
  }
  if (a.instrument == "datum_ball") {
    if (!a.artifacts.empty()) return PlanUsageError("--artifacts is for --instrument probe_artifacts, not datum_ball");
    if (a.probe_radius_mm)
      return PlanUsageError("--probe-radius-mm is for --instrument probe_artifacts, not datum_ball");
  } else {
    if (!b.ball_part_mm.empty()) return PlanUsageError("--ball is for --instrument datum_ball, not probe_artifacts");
    if (b.ball_diameter_mm)
      return PlanUsageError("--ball-diameter is for --instrument datum_ball, not probe_artifacts");
  }
  return Status::Ok();
}

// All outputs are computed and checked by the stage before the first is written.
int RunDatumBallPlan(const PlanArgs& args) {
  pipeline::DatumBallPlanRequest request = args.ball;
  request.machine_path = args.piece.machine;
  request.csv_path = args.out;
  const std::string table = request.nc.output.empty() ? std::string() : request.nc.output + ".tbl";
  if (Status s = CheckDistinctOutputs({{"-o", args.out}, {"--nc", request.nc.output}, {"--nc (tool table)", table}}); !s.ok())
    return ReportError(s);
  auto stage = pipeline::RunDatumBallPlanStage(request);
  if (!stage.ok()) return ReportError(stage.status());
  Info(fmt::format("tpcal plan: datum ball on {}: {} rotary positions, ball D {} mm at part ({}, {}, {}) mm", stage->machine,
                   stage->plan.positions.size(), stage->plan.ball_diameter_mm, stage->plan.ball_part_mm.x(),
                   stage->plan.ball_part_mm.y(), stage->plan.ball_part_mm.z()));
  if (request.machine_path.empty()) Info("tpcal plan: no --machine: nominal bc_table with unlimited strokes");
  for (const pipeline::GcodeFile& f : stage->files) {
    if (Status s = pipeline::WriteFileAtomic(f.path, f.text); !s.ok()) return ReportError(s);
  }
  Info("wrote " + args.out + " (tpcal ballpos v1: the nominal centring commands, mm)");
  if (stage->posted) {
    Info(fmt::format("wrote {} ({}, {} blocks, {} touches, time estimate {:.0f} s)", request.nc.output,
                     gcode::DialectTitle(stage->options.dialect), stage->posted->posted.block_count,
                     5 * stage->plan.positions.size(), stage->posted->ir.duration_s));
    if (!stage->posted->tool_table_text.empty()) Info("wrote " + table + " (LinuxCNC tool table, inches)");
  }
  return kExitOk;
}

// As RunDatumBallPlan: the stage computes and checks every output before the first is written.
int RunProbeArtifactsPlan(const PlanArgs& args) {
  pipeline::ProbeArtifactsPlanRequest request;
  request.machine_path = args.piece.machine;
  request.artifacts_path = args.artifacts;
  request.csv_path = args.out;
  request.nc = args.ball.nc;
  if (!args.ball.tilt_deg.empty()) request.plan.a_deg = args.ball.tilt_deg;
  if (args.ball.c_step_deg) request.plan.c_step_deg = *args.ball.c_step_deg;
  if (args.probe_radius_mm) request.plan.probe_radius_mm = *args.probe_radius_mm;
  const std::string table = request.nc.output.empty() ? std::string() : request.nc.output + ".tbl";
  if (Status s = CheckDistinctOutputs({{"-o", args.out}, {"--nc", request.nc.output}, {"--nc (tool table)", table}}); !s.ok())
    return ReportError(s);
  auto stage = pipeline::RunProbeArtifactsPlanStage(request);
  if (!stage.ok()) return ReportError(stage.status());
  Info(fmt::format("tpcal plan: probe artifacts on {}: {} artifacts, {} rotary poses, {} touches planned, {} skipped, "
                   "stylus radius {} mm",
                   stage->machine, stage->plan.artifacts.boxes.size(), stage->plan.poses.size(),
                   stage->plan.touches.size(), stage->plan.skipped.size(), stage->plan.probe_radius_mm));
  if (request.machine_path.empty()) Info("tpcal plan: no --machine: nominal ac_table with unlimited strokes");
  if (request.artifacts_path.empty()) Info("tpcal plan: no --artifacts: seed 000's three 30 x 30 x 60 mm columns");
  for (const std::string& line : stage->skipped_lines) Info(line);
  for (const pipeline::GcodeFile& f : stage->files) {
    if (Status s = pipeline::WriteFileAtomic(f.path, f.text); !s.ok()) return ReportError(s);
  }
  Info("wrote " + args.out + " (tpcal probepts v1 plan: the nominal contact points and approaches, machine frame, mm)");
  if (stage->posted) {
    Info(fmt::format("wrote {} ({}, {} blocks, {} touches, time estimate {:.0f} s)", request.nc.output,
                     gcode::DialectTitle(stage->options.dialect), stage->posted->posted.block_count,
                     stage->plan.touches.size(), stage->posted->ir.duration_s));
    if (!stage->posted->tool_table_text.empty()) Info("wrote " + table + " (LinuxCNC tool table, inches)");
  }
  return kExitOk;
}

// As RunDatumBallPlan: the stage computes and checks every output before the first is written.
int RunBallbarPlan(const PlanArgs& args) {
  pipeline::BallbarPlanRequest request;
  request.setup_path = args.setup;
  request.machine_path = args.piece.machine;
  request.angles = args.bar_angles;
  request.csv_path = args.out;
  request.nc = args.ball.nc;
  if (args.bar_feed_mm_per_min) request.program.feed_mm_per_min = *args.bar_feed_mm_per_min;
  const std::string table = request.nc.output.empty() ? std::string() : request.nc.output + ".tbl";
  const Status distinct =
      CheckDistinctOutputs({{"-o", args.out}, {"--nc", request.nc.output}, {"--nc (tool table)", table}});
  if (!distinct.ok()) return ReportError(distinct);
  auto stage = pipeline::RunBallbarPlanStage(request);
  if (!stage.ok()) return ReportError(stage.status());
  Info(fmt::format("tpcal plan: ball bar on {}: {} installations, {} readings", stage->machine, stage->tests.size(),
                   stage->readings.rows.size()));
  if (request.machine_path.empty()) Info("tpcal plan: no --machine: nominal bhead_ctable with unlimited strokes");
  for (const pipeline::GcodeFile& f : stage->files) {
    if (Status s = pipeline::WriteFileAtomic(f.path, f.text); !s.ok()) return ReportError(s);
  }
  Info("wrote " + args.out + " (tpcal ballbar v1 plan: the readings to take, dl_um 0)");
  if (stage->posted) {
    Info(fmt::format("wrote {} ({}, {} blocks, {} installations, time estimate {:.0f} s)", request.nc.output,
                     gcode::DialectTitle(stage->options.dialect), stage->posted->posted.block_count,
                     stage->tests.size(), stage->posted->ir.duration_s));
    if (!stage->posted->tool_table_text.empty()) Info("wrote " + table + " (LinuxCNC tool table, inches)");
  }
  return kExitOk;
}

int RunPlan(const PlanArgs& args) {
  if (Status s = CheckPlanMode(args); !s.ok()) return ReportError(s);
  if (args.instrument == "ballbar") return RunBallbarPlan(args);
  if (args.instrument == "probe_artifacts") return RunProbeArtifactsPlan(args);
  if (!args.instrument.empty()) return RunDatumBallPlan(args);
  if (Status s = CheckDistinctOutputs({{"-o", args.out}, {"--step", args.step}, {"--write-config", args.write_config}, {"--dmis", args.dmis}});
      !s.ok())
    return ReportError(s);
  auto built = BuildPiece(args.piece);
  if (!built.ok()) return ReportError(built.status());
  Info(fmt::format("tpcal plan: {} on {}, {} operations, {:.1f} min of machining", built->piece.name,
                   kinematics::MachineTypeName(built->machine.type), built->piece.operations.size(),
                   built->piece.duration_s() / 60.0));
  auto plan = pipeline::RunPlanStage(*built, args.out);
  if (!plan.ok()) return ReportError(plan.status());
  auto dmis = args.dmis.empty() ? Result<std::string>(std::string()) : testpieces::FormatDmisProgram(built->piece, plan->plan);
  if (!dmis.ok()) return ReportError(dmis.status().WithLocation(args.dmis));

  if (!args.step.empty()) {
    Info("building the B-rep (OpenCASCADE) for " + args.step);
    Status s = pipeline::WriteFileAtomicVia(
        args.step, [&](const std::string& temp) { return testpieces::WriteStep(built->piece, temp); });
    if (!s.ok()) return ReportError(s.file().empty() ? s.WithLocation(args.step) : s);
    Info("wrote " + args.step);
  }
  if (Status s = pipeline::WriteFileAtomic(args.out, plan->csv); !s.ok()) return ReportError(s);
  Info(fmt::format("wrote {}: {} points on {} features (datum frame, mm)", args.out, plan->points.size(),
                   plan->points.feature_names.size()));
  if (Status s = WriteEffectiveConfig(args.write_config, *built); !s.ok()) return ReportError(s);
  if (!args.write_config.empty()) Info("wrote " + args.write_config);
  if (Status s = args.dmis.empty() ? Status::Ok() : pipeline::WriteFileAtomic(args.dmis, *dmis); !s.ok()) return ReportError(s);
  if (!args.dmis.empty()) Info("wrote " + args.dmis + " (DMIS inspection program, docs/formats/dmis.md)");
  return kExitOk;
}

}  // namespace

Command RegisterPlan(CLI::App& app) {
  auto args = std::make_shared<PlanArgs>();
  CLI::App* sub = app.add_subcommand(
      "plan",
      "Write the CMM probing plan of a test piece (tpcal plan v1 CSV).\n"
      "One row per point to probe: feature label, nominal point x,y,z (mm) and outward unit normal i,j,k in the\n"
      "part's datum frame (turning piece: z = 0 on B_R, origin at the S_R centre, +X toward H1), then the machine\n"
      "state that cut it: op (1 = first operation), t_s (s from the start of machining), the rotary axes in deg\n"
      "(A_deg, C_deg on A/C tables; B_deg on B/C), and X_mm, Y_mm, Z_mm of the tool reference point.\n"
      "With --instrument datum_ball: the plan of a datum-ball test (tpcal ballpos v1) and its probing program.\n"
      "With --instrument probe_artifacts: the plan of an on-machine probing test of artifacts (tpcal probepts v1:\n"
      "A_deg, C_deg, artifact, face, nominal contact x,y,z in mm and approach i,j,k, machine frame) and its program.\n"
      "With --instrument ballbar: the readings of a double-ball-bar test (tpcal ballbar v1: setup, angle_deg,\n"
      "dl_um 0) and its program.");
  AddPieceOptions(sub, &args->piece, /*machine_required=*/false);
  sub->get_option("--testpiece")->required(false);  // or --instrument
  sub->add_option("-o,--output", args->out, "plan CSV to write (docs/formats/probing_plan.md)")->required();
  sub->add_option("--step", args->step, "also write the nominal B-rep of the piece as AP214 STEP (part frame, mm)");
  sub->add_option("--write-config", args->write_config,
                  "also write the effective test-piece configuration (every key, defaults included) as YAML");
  sub->add_option("--dmis", args->dmis, "also write the plan as a DMIS inspection program (.dmi, docs/formats/dmis.md)");
  pipeline::DatumBallPlanRequest& b = args->ball;
  sub->add_option("--instrument", args->instrument,
                  "datum_ball: plan a datum-ball test instead of a test piece (seed 001; a ball on the rotary table "
                  "centred by a spindle touch probe at each rotary position): -o gets the nominal centring commands "
                  "as tpcal ballpos v1 (what an error-free machine reads), --nc the probing program; --machine is the "
                  "B/C or A/C table (default: the nominal bc_table). probe_artifacts: plan an on-machine probing test "
                  "of artifacts (seed 000; square columns on the table touched at the centre of every face at each "
                  "A x C pose): -o gets the nominal contact points x,y,z (mm) and approach directions i,j,k (machine "
                  "frame) as tpcal probepts v1 (docs/formats/probepts.md), one row per planned touch; touches a "
                  "collision rules out (face down, corridor blocked) are listed on stderr with their reason; --nc the "
                  "probing program; --machine is the A/C table (default: the nominal ac_table). ballbar: plan a "
                  "double-ball-bar test (seed 003; ISO 230-4 circular tests) of the installations of --setup: -o "
                  "gets one row per reading to take as tpcal ballbar v1 (docs/formats/ballbar.md: setup, angle_deg, "
                  "dl_um 0, and direction cw/ccw when a circle is planned), --nc the test program (the rotary axis "
                  "indexed with the tool ball following, or the circle ccw then cw); --machine default: the nominal "
                  "bhead_ctable")
      ->check(CLI::IsMember({"datum_ball", "probe_artifacts", "ballbar"}));
  sub->add_option("--setup", args->setup,
                  "ballbar: the installations, YAML (schema tpcal.ballbar_setup/1, docs/formats/ballbar_setup.md; "
                  "part / tool frame, mm), e.g. samples/ballbar/seed003_setups.yaml");
  sub->add_option("--angles-deg", args->bar_angles.angles_deg,
                  "ballbar: the angles of every installation, deg (rotary command, or a circle's path angle); default "
                  "C 0..360 every 20, A or B 0..-100 every 5, circles 0..359 every 1 (seed 003)")
      ->delimiter(',');
  sub->add_option("--step-deg", args->bar_angles.step_deg,
                  "ballbar: the default ranges in this step, deg (instead of 20 / 5 / 1)");
  sub->add_option("--feed-mm-per-min", args->bar_feed_mm_per_min,
                  "ballbar: contouring feed of the circular tests in --nc, mm/min; default 1000");
  sub->add_option("--tilt-deg", b.tilt_deg,
                  "datum_ball: tilt-axis (B or A) commands, deg; default 0,30,-30. probe_artifacts: A commands, deg; "
                  "default 0,-30,-60,-90")
      ->delimiter(',');
  sub->add_option("--c-step-deg", b.c_step_deg,
                  "C from 0 to < 360 deg in this step, deg; default 30 (datum_ball), 60 (probe_artifacts)");
  sub->add_option("--ball", b.ball_part_mm, "datum_ball: nominal ball centre x,y,z in the part frame, mm; default 200,0.1,300")
      ->delimiter(',');
  sub->add_option("--ball-diameter", b.ball_diameter_mm, "datum_ball: ball diameter, mm; default 25");
  sub->add_option("--artifacts", args->artifacts,
                  "probe_artifacts: the artifact boxes, YAML (schema tpcal.artifacts/1, docs/formats/artifacts.md; "
                  "part frame, mm); default: seed 000's three 30 x 30 x 60 mm columns at (100, 0), (-100, 0), (0, 100) mm");
  sub->add_option("--probe-radius-mm", args->probe_radius_mm,
                  "probe_artifacts: stylus ball radius, mm (the collision corridors grow by it); default 3");
  sub->add_option("--nc", b.nc.output,
                  "also write the probing NC program (gcode/DIALECTS.md; datum_ball: 5 touches per position; "
                  "probe_artifacts: one touch per planned face; ballbar: the test, M0 to mount and to remove the bar "
                  "at each installation, a dwell per reading); its stem (upper case) names the program; LinuxCNC "
                  "also gets PROGRAM.tbl");
  sub->add_option("--dialect", b.nc.dialect,
                  "controller of --nc: fanuc, linuxcnc, sinumerik, heidenhain; default: from the extension of --nc "
                  "(.nc, .ngc, .mpf, .h)");
  sub->add_option("--post", b.nc.post_path, "post options YAML for --nc (schema tpcal.gcode/1)");
  sub->add_option("--date", b.nc.date, "header date of --nc, YYYY-MM-DD or none; default: today (UTC)");
  return {sub, [args] { return RunPlan(*args); }};
}

}  // namespace tpcal::cli
