// tpcal fit POINTS [--plan PLAN.yaml | --testpiece NAME [--config TP.yaml] [--machine M.yaml]
//           [--anchor FEATURE@X,Y,Z]] [--type FEATURE=KIND ...] [--criterion ls|mz] [--json OUT]
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/units.h"
#include "gdt/inspection.h"
#include "gdt/plan_yaml.h"
#include "pipeline/io/atomic_file.h"
#include "pipeline/cli/anchor_option.h"
#include "pipeline/cli/commands.h"
#include "pipeline/report/fit_json.h"
#include "pipeline/piece_loader.h"
#include "pipeline/io/point_io.h"
#include "pipeline/raw_scan_labeling.h"
#include "testpieces/named_pieces.h"

namespace tpcal::cli {
namespace {

struct FitArgs {
  std::string points;
  std::string plan;
  std::vector<std::string> types;
  std::string criterion;
  std::string json;
  int threads = 0;
  std::string testpiece;  // optional: label a raw scan by this piece; its inspection plan by default
  std::string config;
  std::string machine;
  std::string anchor;  // FEATURE@X,Y,Z: with --testpiece, the symmetric labelling of a raw scan
};

Result<std::map<std::string, gdt::FeatureKind>> ParseTypes(const std::vector<std::string>& types) {
  std::map<std::string, gdt::FeatureKind> kinds;
  for (const auto& t : types) {
    const auto eq = t.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == t.size())
      return Status(StatusCode::kInvalidArgument, "--type expects FEATURE=KIND, got '" + t + "'");
    const auto kind = gdt::ParseFeatureKind(t.substr(eq + 1));
    if (!kind)
      return Status(StatusCode::kInvalidArgument,
                    "--type " + t + ": unknown kind '" + t.substr(eq + 1) +
                        "' (expected line2, line3, plane, circle, cylinder, sphere, cone or point)");
    kinds[t.substr(0, eq)] = *kind;
  }
  return kinds;
}

void PrintSummary(const gdt::InspectionResult& r) {
  std::cout << fmt::format("{:<12} {:<13} {:>7} {:>10} {:>10}\n", "feature", "kind", "points", "rms_um", "form_um");
  for (const auto& f : r.features) {
    std::size_t n = 0;
    double rms_mm = 0;
    std::visit([&](const auto& fit) { n = fit.n_points; rms_mm = fit.stats.rms_mm; }, f.fit);
    const auto form = f.form_mm();
    std::cout << fmt::format("{:<12} {:<13} {:>7} {:>10.3f} {:>10}\n", f.name, gdt::FeatureKindName(f.kind), n,
                             MmToUm(rms_mm), form ? fmt::format("{:.3f}", MmToUm(*form)) : std::string("-"));
  }
  if (!r.characteristics.empty()) std::cout << "\n";
  for (const auto& c : r.characteristics) {
    std::string values;
    for (const auto& v : c.values) values += fmt::format("  {}={:.4g}", v.name, v.value);
    std::cout << fmt::format("{:<28} {:<14}{}\n", c.name, gdt::CharacteristicTypeName(c.type), values);
  }
}

int RunFit(const FitArgs& args) {
  auto labelling = ParseAnchor(args.anchor);
  if (!labelling.ok()) return ReportError(labelling.status());
  if (!args.anchor.empty() && args.testpiece.empty())
    return ReportError(Status(StatusCode::kInvalidArgument, "--anchor needs --testpiece"));
  pipeline::PointReadOptions read_options;
  read_options.threads = args.threads;
  auto points = pipeline::ReadPoints(args.points, read_options);
  if (!points.ok()) return ReportError(points.status());

  auto kinds = ParseTypes(args.types);
  if (!kinds.ok()) return ReportError(kinds.status());

  // With a test piece: a raw scan (no feature labels) is labelled by the piece's nominal
  // features, and the piece's inspection plan is evaluated unless --plan names another.
  std::optional<gdt::InspectionPlan> plan;
  if (!args.testpiece.empty()) {
    auto setup = pipeline::LoadPiece({.testpiece = args.testpiece, .config_path = args.config, .machine_path = args.machine,
                                    .wording = {.name_piece_errors = true}});
    if (!setup.ok()) return ReportError(setup.status());
    auto labelled = pipeline::LabelIfRawScan(setup->piece, &*points, *labelling);
    if (!labelled.ok()) return ReportError(labelled.status());
    if (labelled->has_value()) Info("raw scan labelled: " + (*labelled)->BriefReport());
    if (args.plan.empty()) plan = setup->piece.inspection;
  } else if (!args.config.empty() || !args.machine.empty()) {
    return ReportError(Status(StatusCode::kInvalidArgument, "--config and --machine need --testpiece"));
  } else if (!points->has_labels()) {
    return ReportError(Status(StatusCode::kInvalidArgument,
                              "no point carries a feature label (a raw scan): give --testpiece NAME to label it "
                              "by the piece's nominal features",
                              args.points));
  }
  if (!args.plan.empty()) {
    auto loaded = gdt::LoadInspectionPlan(args.plan);
    if (!loaded.ok()) return ReportError(loaded.status());
    plan = std::move(*loaded);
  }
  if (plan) {
    for (const auto& [name, kind] : *kinds) {
      bool found = false;
      for (auto& f : plan->features)
        if (f.name == name) { f.kind = kind; found = true; }
      if (!found)
        return ReportError(Status(StatusCode::kInvalidArgument,
                                  "--type " + name + ": the plan has no feature of that name", args.plan));
    }
  } else {
    gdt::AdHocOptions adhoc;
    adhoc.kinds = *kinds;
    auto built = gdt::AdHocPlan(*points, adhoc);
    if (!built.ok()) return ReportError(built.status().code() == StatusCode::kInvalidArgument && built.status().file().empty()
                                            ? built.status().WithLocation(args.points)
                                            : built.status());
    plan = std::move(*built);
  }
  if (!args.criterion.empty()) {
    const auto crit = gdt::ParseFormCriterion(args.criterion);
    for (auto& f : plan->features) f.form_criterion = *crit;
  }

  Info(fmt::format("tpcal fit: {} points, {} features from {}", points->size(), plan->features.size(), args.points));
  auto result = gdt::EvaluatePlan(*plan, *points);
  if (!result.ok()) return ReportError(result.status());

  const std::string json = pipeline::FitResultJson(*result);
  if (args.json == "-") {
    std::cout << json;
  } else {
    PrintSummary(*result);
    if (!args.json.empty()) {
      if (Status s = pipeline::WriteFileAtomic(args.json, json); !s.ok()) return ReportError(s);
      Info("wrote " + args.json);
    }
  }
  return kExitOk;
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
  sub->add_option("POINTS", args->points, "point file: tpcal points CSV, PLY, PCD or x y z [i j k] text (mm)")
      ->required();
  sub->add_option("--plan", args->plan, "inspection plan YAML (schema tpcal.inspection_plan/1)");
  sub->add_option("--type", args->types, "FEATURE=KIND: fit FEATURE as KIND (line2, line3, plane, circle, cylinder, sphere, cone, point)");
  sub->add_option("--criterion", args->criterion, "form criterion of every feature: ls (least squares) or mz (minimum zone)")
      ->check(CLI::IsMember({"ls", "mz"}));
  sub->add_option("--json", args->json, "write the result as JSON (schema tpcal.fit/1) to this file; '-' for stdout");
  sub->add_option("--testpiece", args->testpiece,
                  "test piece whose nominal features label a raw scan (points without labels); its inspection "
                  "plan is evaluated unless --plan is given: " + names);
  sub->add_option("--config", args->config, "test-piece configuration YAML (schema tpcal.testpiece/1; with --testpiece)");
  sub->add_option("--machine", args->machine, "machine model YAML (with --testpiece; default: nominal ac_table or xyz)");
  AddAnchorOption(sub, &args->anchor);
  sub->add_option("--threads", args->threads, "parser threads (0 = all cores)")->capture_default_str();
  return {sub, [args] { return RunFit(*args); }};
}

}  // namespace tpcal::cli
