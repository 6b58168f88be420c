// tpcal fit POINTS [--plan PLAN.yaml | --testpiece NAME [--config TP.yaml] [--machine M.yaml]
//           [--anchor FEATURE@X,Y,Z]] [--type FEATURE=KIND ...] [--criterion ls|mz] [--json OUT]
#include <CLI/CLI.hpp>

#include <memory>
#include <string>

#include "pipeline/cli/anchor_option.h"
#include "pipeline/cli/column_option.h"
#include "pipeline/cli/commands.h"
#include "pipeline/fit_stage.h"
#include "pipeline/report/fit_json.h"
#include "testpieces/named_pieces.h"

namespace tpcal::cli {
namespace {

struct FitArgs {
  pipeline::FitRequest request;
  std::string json;
  std::string anchor;  // FEATURE@X,Y,Z: with --testpiece, the symmetric labelling of a raw scan
};

int RunFit(const FitArgs& args) {
  auto labelling = ParseAnchor(args.anchor);
  if (!labelling.ok()) return ReportError(labelling.status());
  if (!args.anchor.empty() && args.request.testpiece.empty())
    return ReportError(Status(StatusCode::kInvalidArgument, "--anchor needs --testpiece"));
  pipeline::FitRequest request = args.request;
  request.labelling = *labelling;
  request.info = Info;
  auto result = pipeline::RunFitStage(request);
  if (!result.ok()) return ReportError(result.status());
  return WriteJsonOrText(args.json, pipeline::FitResultJson(*result), [&] { return pipeline::FitSummary(*result); });
}

}  // namespace

Command RegisterFit(CLI::App& app) {
  auto args = std::make_shared<FitArgs>();
  const std::string names = testpieces::PieceNameList();
  CLI::App* sub = app.add_subcommand(
      "fit",
      "Fit features and evaluate GD&T from CMM points.\n"
      "Least-squares (ISO 10360-6) fits of every feature, the datum frame and the characteristics of an\n"
      "inspection plan (samples/plans/turning.yaml for the seed 002 turning test piece). Without a plan every\n"
      "labelled feature is fitted in the CMM frame, its kind taken from --type or inferred from the normals.\n"
      "A raw scan (no feature labels) needs --testpiece: its points are assigned to the piece's nominal features.");
  sub->add_option("POINTS", args->request.points_path, "point file: tpcal points CSV, PLY, PCD or x y z [i j k] text (mm)")
      ->required();
  sub->add_option("--plan", args->request.plan_path, "inspection plan YAML (schema tpcal.inspection_plan/1)");
  sub->add_option("--type", args->request.types, "FEATURE=KIND: fit FEATURE as KIND (line2, line3, plane, circle, cylinder, sphere, cone, point)");
  sub->add_option("--criterion", args->request.criterion, "form criterion of every feature: ls (least squares) or mz (minimum zone)")
      ->check(CLI::IsMember({"ls", "mz"}));
  sub->add_option("--json", args->json, "write the result as JSON (schema tpcal.fit/1) to this file; '-' for stdout");
  sub->add_option("--testpiece", args->request.testpiece,
                  "test piece whose nominal features label a raw scan (points without labels); its inspection "
                  "plan is evaluated unless --plan is given: " + names);
  sub->add_option("--config", args->request.config_path, "test-piece configuration YAML (schema tpcal.testpiece/1; with --testpiece)");
  sub->add_option("--machine", args->request.machine_path, "machine model YAML (with --testpiece; default: nominal ac_table or xyz)");
  AddAnchorOption(sub, &args->anchor);
  AddColumnOption(sub, &args->request.columns);
  sub->add_option("--threads", args->request.threads, "parser threads (0 = all cores)")->capture_default_str();
  return {sub, [args] { return RunFit(*args); }};
}

}  // namespace tpcal::cli
