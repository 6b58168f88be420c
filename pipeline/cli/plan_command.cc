// tpcal plan --testpiece NAME [--config TP.yaml] [--machine M.yaml] [--density paper|dense|N]
//            [--levels N] -o PLAN.csv [--step PIECE.step] [--write-config TP_OUT.yaml]
//
// Writes the CMM probing plan of a test piece as the `tpcal plan v1` CSV (docs/formats/probing_plan.md):
// nominal points and outward normals in the part's DATUM frame, then op, t_s, the
// rotary axes (A_deg/B_deg, C_deg: those the machine has), X_mm, Y_mm, Z_mm of the machine
// state that cut each point (pipeline/plan_stage.h).
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <memory>
#include <string>

#include "pipeline/cli/commands.h"
#include "pipeline/cli/piece_args.h"
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
};

int RunPlan(const PlanArgs& args) {
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
      "(A_deg, C_deg on A/C tables; B_deg on B/C), and X_mm, Y_mm, Z_mm of the tool reference point.");
  AddPieceOptions(sub, &args->piece, /*machine_required=*/false);
  sub->add_option("-o,--output", args->out, "plan CSV to write (docs/formats/probing_plan.md)")->required();
  sub->add_option("--step", args->step, "also write the nominal B-rep of the piece as AP214 STEP (part frame, mm)");
  sub->add_option("--write-config", args->write_config,
                  "also write the effective test-piece configuration (every key, defaults included) as YAML");
  sub->add_option("--dmis", args->dmis, "also write the plan as a DMIS inspection program (.dmi, docs/formats/dmis.md)");
  return {sub, [args] { return RunPlan(*args); }};
}

}  // namespace tpcal::cli
