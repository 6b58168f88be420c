// tpcal plan --testpiece NAME [--config TP.yaml] [--machine M.yaml] [--density paper|dense|N]
//            [--levels N] -o PLAN.csv [--step PIECE.step] [--write-config TP_OUT.yaml]
// tpcal plan --instrument datum_ball [--machine M.yaml] [--tilt-deg 0,30,-30] [--c-step-deg 30]
//            [--ball X,Y,Z] [--ball-diameter D] -o PLAN.csv [--nc PROGRAM [--dialect D] [--post P.yaml]
//            [--date YYYY-MM-DD|none]]
//
// Writes the CMM probing plan of a test piece as the `tpcal plan v1` CSV (docs/formats/probing_plan.md):
// nominal points and outward normals in the part's DATUM frame, then op, t_s, the
// rotary axes (A_deg/B_deg, C_deg: those the machine has), X_mm, Y_mm, Z_mm of the machine
// state that cut each point (pipeline/plan_stage.h).
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "pipeline/cli/commands.h"
#include "pipeline/cli/piece_args.h"
#include "pipeline/datum_ball_plan_stage.h"
#include "pipeline/io/atomic_file.h"
#include "pipeline/plan_stage.h"
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
  std::string instrument;  // "" = a test piece; datum_ball
  pipeline::DatumBallPlanRequest ball;
};

Status PlanUsageError(const std::string& message) { return Status(StatusCode::kInvalidArgument, message, "tpcal plan"); }

// The options of one mode used in the other are errors, not silently ignored.
Status CheckPlanMode(const PlanArgs& a) {
  const pipeline::DatumBallPlanRequest& b = a.ball;
  if (a.instrument.empty()) {
    if (a.piece.testpiece.empty()) return PlanUsageError("--testpiece NAME (or --instrument datum_ball) is required");
    for (const auto& [name, set] : std::vector<std::pair<std::string, bool>>{
             {"--tilt-deg", !b.tilt_deg.empty()}, {"--c-step-deg", b.c_step_deg.has_value()},
             {"--ball", !b.ball_part_mm.empty()}, {"--ball-diameter", b.ball_diameter_mm.has_value()},
             {"--nc", !b.nc.output.empty()}, {"--dialect", !b.nc.dialect.empty()}, {"--post", !b.nc.post_path.empty()},
             {"--date", !b.nc.date.empty()}}) {
      if (set) return PlanUsageError(name + " needs --instrument datum_ball");
    }
    return Status::Ok();
  }
  for (const auto& [name, set] : std::vector<std::pair<std::string, bool>>{
           {"--testpiece", !a.piece.testpiece.empty()}, {"--config", !a.piece.config.empty()},
           {"--density", !a.piece.density.empty()}, {"--levels", a.piece.levels.has_value()},
           {"--step", !a.step.empty()}, {"--write-config", !a.write_config.empty()}, {"--dmis", !a.dmis.empty()}}) {
    if (set) return PlanUsageError(name + " is for test pieces, not --instrument datum_ball");
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

int RunPlan(const PlanArgs& args) {
  if (Status s = CheckPlanMode(args); !s.ok()) return ReportError(s);
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
      "With --instrument datum_ball: the plan of a datum-ball test (tpcal ballpos v1) and its probing program.");
  AddPieceOptions(sub, &args->piece, /*machine_required=*/false);
  sub->get_option("--testpiece")->required(false);  // or --instrument datum_ball
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
                  "B/C or A/C table (default: the nominal bc_table)")
      ->check(CLI::IsMember({"datum_ball"}));
  sub->add_option("--tilt-deg", b.tilt_deg, "datum_ball: tilt-axis (B or A) commands, deg; default 0,30,-30")
      ->delimiter(',');
  sub->add_option("--c-step-deg", b.c_step_deg, "datum_ball: C from 0 to < 360 deg in this step; default 30");
  sub->add_option("--ball", b.ball_part_mm, "datum_ball: nominal ball centre x,y,z in the part frame, mm; default 200,0.1,300")
      ->delimiter(',');
  sub->add_option("--ball-diameter", b.ball_diameter_mm, "datum_ball: ball diameter, mm; default 25");
  sub->add_option("--nc", b.nc.output,
                  "datum_ball: also write the probing NC program (5 touches per position, gcode/DIALECTS.md); its "
                  "stem (upper case) names the program; LinuxCNC also gets PROGRAM.tbl");
  sub->add_option("--dialect", b.nc.dialect,
                  "datum_ball: controller of --nc: fanuc, linuxcnc, sinumerik, heidenhain; default: from the "
                  "extension of --nc (.nc, .ngc, .mpf, .h)");
  sub->add_option("--post", b.nc.post_path, "datum_ball: post options YAML for --nc (schema tpcal.gcode/1)");
  sub->add_option("--date", b.nc.date, "datum_ball: header date of --nc, YYYY-MM-DD or none; default: today (UTC)");
  return {sub, [args] { return RunPlan(*args); }};
}

}  // namespace tpcal::cli
