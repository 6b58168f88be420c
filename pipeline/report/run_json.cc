#include "pipeline/report/run_json.h"

#include "pipeline/report/diagnosis_json.h"
#include "pipeline/report/fit_json.h"
#include "pipeline/report/identification_blocks.h"
#include "pipeline/report/json_util.h"
#include "pipeline/report/screen_json.h"
#include "pipeline/version.h"

namespace tpcal::pipeline {
namespace {

using Json = nlohmann::ordered_json;

Json ConfigJson(const RunSettings& c) {
  Json j = {{"schema", "tpcal.pipeline/1"},
          {"testpiece", c.testpiece},
          {"points", c.points},
          {"machine", c.machine},
          {"parameters", c.parameters},
          {"seed", c.seed},
          {"uncertainty",
           {{"primary", kinematics::UncertaintyMethodName(c.primary)},
            {"jackknife_groups", c.jackknife_groups},
            {"monte_carlo_trials", c.monte_carlo_trials}}},
          {"diagnose", c.diagnose},
          {"truth", c.truth},
          {"report",
           {{"position_magnification", c.figures.position_magnification},
            {"profile_magnification", c.figures.profile_magnification}}}};
  if (!c.reference_file.empty())
    j["reference"] = {{"instrument", c.reference_instrument}, {"file", c.reference_file}};
  return j;
}

}  // namespace

std::string RunReportJson(const RunReport& r) {
  const auto& id = *r.identification;
  Json params = Json::array();
  for (const auto& p : id.parameters) {
    Json j = ParameterEstimateJson(p);
    j["primary_method"] = kinematics::UncertaintyMethodName(r.settings.primary);
    if (auto it = r.truth->find(p.name); it != r.truth->end()) j["truth"] = it->second;
    params.push_back(std::move(j));
  }

  Json figures = Json::array();
  for (const auto& f : *r.figures) figures.push_back(f.name);

  Json out = {
      {"schema", "tpcal.run/1"},
      {"tpcal", {{"version", kVersion}, {"git_revision", kGitRevision}}},
      {"seed", r.settings.seed},
      {"config", ConfigJson(r.settings)},
      {"input",
       {{"points", r.settings.points},
        {"format", r.input.format},
        {"digest_xxh64", r.input.digest_xxh64},
        {"num_points", r.input.num_points},
        {"source_units", r.input.source_units}}},
      {"piece", r.piece_name},
      {"machine", r.machine_name},
      {"inspection", FitResultJsonValue(*r.inspection)},
      {"identification",
       {{"n_points", id.num_observations},
        {"n_features", id.num_groups},
        {"parameters", std::move(params)},
        {"identifiability", IdentifiabilityJson(id)},
        {"fit", IdentificationFitJson(id)},
        {"alignment", RigidJson(id.alignment)}}},
      {"figures", std::move(figures)}};
  if (!r.identification_outliers->empty()) {
    out["identification"]["outliers"] = OutliersJson(*r.identification_outliers);
    out["identification"]["local_defects"] = LocalDefectsJson(*r.identification_local_defects);
  }
  if (r.scan_cells) {
    const ScanCellsSummary& c = *r.scan_cells;
    out["input"]["scan_cells"] = {{"num_points", c.num_points},
                                  {"num_cells", c.num_cells},
                                  {"mean_points_per_cell", c.mean_points_per_cell},
                                  {"max_points_per_cell", c.max_points_per_cell},
                                  {"max_cell_mm", c.max_cell_mm},
                                  {"max_cell_deg", c.max_cell_deg},
                                  {"layout", c.on_grid ? "grid" : "scan_line"},
                                  {"flagged_hits", c.flagged_hits},
                                  {"hit_sigma_um", c.hit_sigma_um},
                                  {"note", c.on_grid ? "identification and diagnosis ran on one observation per grid "
                                                       "cell (the file is not in scan order)"
                                                     : "identification and diagnosis ran on one observation per "
                                                       "scan-line cell"}};
  }
  if (r.raw_scan) {
    const RawScanSummary& l = *r.raw_scan;
    Json counts = Json::object();
    for (const auto& [feature, points] : l.points_per_feature) counts[feature] = points;
    out["input"]["raw_scan"] = {{"num_points", l.num_points},
                                {"num_labelled", l.num_points - l.num_rejected},
                                {"num_rejected", l.num_rejected},
                                {"labelled_fraction", l.labelled_fraction},
                                {"rms_distance_um", l.rms_distance_um},
                                {"symmetry_order", l.symmetry_order},
                                {"symmetry_resolved_by", l.symmetry_resolved_by},
                                {"part_from_cmm", RigidJson(l.part_from_cmm)},
                                {"points_per_feature", std::move(counts)},
                                {"message", l.message}};
  }
  if (r.diagnosis) {
    out["diagnosis"] = DiagnosisJsonValue(
        *r.diagnosis, {{"points", r.settings.points}, {"testpiece", r.settings.testpiece}, {"machine", r.machine_name}});
  } else if (r.settings.diagnose) {
    out["diagnosis"] = {{"error", r.diagnosis_error}};
  }
  return out.dump(2) + "\n";
}

}  // namespace tpcal::pipeline
