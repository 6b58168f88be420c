#include "pipeline/fit_stage.h"

#include <fmt/format.h>

#include <map>
#include <optional>
#include <variant>

#include "core/units.h"
#include "gdt/plan_yaml.h"
#include "pipeline/io/point_io.h"
#include "pipeline/piece_loader.h"

namespace tpcal::pipeline {
namespace {

Result<std::map<std::string, gdt::FeatureKind>> ParseFeatureTypes(const std::vector<std::string>& types) {
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

}  // namespace

Result<gdt::InspectionResult> RunFitStage(const FitRequest& request) {
  PointReadOptions read_options;
  read_options.threads = request.threads;
  auto columns = ParsePointColumns(request.columns);
  if (!columns.ok()) return columns.status();
  read_options.columns = std::move(*columns);
  auto points = ReadPoints(request.points_path, read_options);
  if (!points.ok()) return points.status();
  auto kinds = ParseFeatureTypes(request.types);
  if (!kinds.ok()) return kinds.status();

  // With a test piece: a raw scan (no feature labels) is labelled by the piece's nominal
  // features, and the piece's inspection plan is evaluated unless plan_path names another.
  std::optional<gdt::InspectionPlan> plan;
  if (!request.testpiece.empty()) {
    auto setup = LoadPiece({.testpiece = request.testpiece, .config_path = request.config_path,
                            .machine_path = request.machine_path, .wording = {.name_piece_errors = true}});
    if (!setup.ok()) return setup.status();
    auto labelled = LabelIfRawScan(setup->piece, &*points, request.labelling);
    if (!labelled.ok()) return labelled.status();
    if (labelled->has_value() && request.info) request.info("raw scan labelled: " + (*labelled)->BriefReport());
    if (request.plan_path.empty()) plan = setup->piece.inspection;
  } else if (!request.config_path.empty() || !request.machine_path.empty()) {
    return Status(StatusCode::kInvalidArgument, "--config and --machine need --testpiece");
  } else if (!points->has_labels()) {
    return Status(StatusCode::kInvalidArgument,
                  "no point carries a feature label (a raw scan): give --testpiece NAME to label it "
                  "by the piece's nominal features",
                  request.points_path);
  }
  if (!request.plan_path.empty()) {
    auto loaded = gdt::LoadInspectionPlan(request.plan_path);
    if (!loaded.ok()) return loaded.status();
    plan = std::move(*loaded);
  }
  if (plan) {
    for (const auto& [name, kind] : *kinds) {
      bool found = false;
      for (auto& f : plan->features)
        if (f.name == name) { f.kind = kind; found = true; }
      if (!found)
        return Status(StatusCode::kInvalidArgument, "--type " + name + ": the plan has no feature of that name",
                      request.plan_path);
    }
  } else {
    gdt::AdHocOptions adhoc;
    adhoc.kinds = *kinds;
    auto built = gdt::AdHocPlan(*points, adhoc);
    if (!built.ok())
      return built.status().code() == StatusCode::kInvalidArgument && built.status().file().empty()
                 ? built.status().WithLocation(request.points_path)
                 : built.status();
    plan = std::move(*built);
  }
  if (!request.criterion.empty()) {
    const auto crit = gdt::ParseFormCriterion(request.criterion);
    for (auto& f : plan->features) f.form_criterion = *crit;
  }

  if (request.info)
    request.info(fmt::format("tpcal fit: {} points, {} features from {}", points->size(), plan->features.size(),
                             request.points_path));
  return gdt::EvaluatePlan(*plan, *points);
}

std::string FitSummary(const gdt::InspectionResult& r) {
  std::string out = fmt::format("{:<12} {:<13} {:>7} {:>10} {:>10}\n", "feature", "kind", "points", "rms_um", "form_um");
  for (const auto& f : r.features) {
    std::size_t n = 0;
    double rms_mm = 0;
    std::visit([&](const auto& fit) { n = fit.n_points; rms_mm = fit.stats.rms_mm; }, f.fit);
    const auto form = f.form_mm();
    out += fmt::format("{:<12} {:<13} {:>7} {:>10.3f} {:>10}\n", f.name, gdt::FeatureKindName(f.kind), n,
                       MmToUm(rms_mm), form ? fmt::format("{:.3f}", MmToUm(*form)) : std::string("-"));
  }
  if (!r.characteristics.empty()) out += "\n";
  for (const auto& c : r.characteristics) {
    std::string values;
    for (const auto& v : c.values) values += fmt::format("  {}={:.4g}", v.name, v.value);
    out += fmt::format("{:<28} {:<14}{}\n", c.name, gdt::CharacteristicTypeName(c.type), values);
  }
  return out;
}

}  // namespace tpcal::pipeline
