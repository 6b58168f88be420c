#include "pipeline/run_json.h"

#include "pipeline/diagnosis_json.h"
#include "pipeline/fit_json.h"
#include "pipeline/json_util.h"
#include "pipeline/version.h"

namespace tpcal::pipeline {
namespace {

using Json = nlohmann::ordered_json;

Json Interval(double lo, double hi) { return Json::array({lo, hi}); }

Json CombinationJson(const kinematics::Combination& c) {
  return {{"text", c.text}, {"names", c.names}, {"coefficients", c.coefficients}, {"value", c.value}, {"u", c.u}};
}

Json ConfigJson(const PipelineConfig& c) {
  return {{"schema", "tpcal.pipeline/1"},
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
}

}  // namespace

std::string RunResultJson(const RunResult& r) {
  const auto& id = r.stage.identification;
  Json params = Json::array();
  for (const auto& p : id.parameters) {
    Json u = Json::object();
    for (const auto& m : p.uncertainties) {
      Json e = {{"available", m.available}};
      if (m.available) {
        e["u"] = m.u;
        e["ci95"] = Interval(m.ci95_low, m.ci95_high);
      }
      if (!m.message.empty()) e["message"] = m.message;
      u[kinematics::UncertaintyMethodName(m.method)] = std::move(e);
    }
    Json j = {{"name", p.name},
              {"iso_symbol", p.iso_symbol},
              {"unit", p.unit},
              {"identifiable", p.identifiable},
              {"value", p.identifiable ? Json(p.value) : Json(nullptr)},
              {"u", p.identifiable ? Json(p.u) : Json(nullptr)},
              {"ci95", p.identifiable ? Interval(p.ci95_low, p.ci95_high) : Json(nullptr)},
              {"primary_method", kinematics::UncertaintyMethodName(r.config.primary)},
              {"uncertainties", std::move(u)}};
    if (auto it = r.truth.find(p.name); it != r.truth.end()) j["truth"] = it->second;
    params.push_back(std::move(j));
  }
  const auto& ia = id.identifiability;
  Json estimable = Json::array(), nulls = Json::array();
  for (const auto& c : ia.estimable) estimable.push_back(CombinationJson(c));
  for (const auto& c : ia.null_directions) nulls.push_back(CombinationJson(c));

  Json figures = Json::array();
  for (const auto& f : r.figures) figures.push_back(f.name);

  Json out = {
      {"schema", "tpcal.run/1"},
      {"tpcal", {{"version", kVersion}, {"git_revision", kGitRevision}}},
      {"seed", r.config.seed},
      {"config", ConfigJson(r.config)},
      {"input",
       {{"points", r.config.points},
        {"format", PointFormatName(r.points_info.format)},
        {"digest_xxh64", r.points_digest},
        {"num_points", r.num_points},
        {"source_units", r.points_info.source_units == LengthUnit::kMm ? "mm" : "in"}}},
      {"piece", r.piece_name},
      {"machine", r.machine_name},
      {"inspection", Json::parse(FitResultJson(r.stage.inspection))},
      {"identification",
       {{"parameters", std::move(params)},
        {"identifiability",
         {{"num_parameters", ia.num_parameters},
          {"rank", ia.rank},
          {"condition_number", ia.condition_number},
          {"singular_values", ia.singular_values},
          {"not_identifiable", ia.not_identifiable},
          {"estimable", std::move(estimable)},
          {"null_directions", std::move(nulls)}}},
        {"num_observations", id.num_observations},
        {"num_groups", id.num_groups},
        {"rms_before_um", id.rms_before_um},
        {"rms_after_um", id.rms_after_um},
        {"sigma_um", id.sigma_um},
        {"iterations", id.iterations},
        {"termination", id.termination},
        {"alignment", RigidJson(id.alignment)}}},
      {"figures", std::move(figures)}};
  if (r.diagnosis) {
    out["diagnosis"] = Json::parse(DiagnosisJson(
        *r.diagnosis, {{"points", r.config.points}, {"testpiece", r.config.testpiece}, {"machine", r.machine_name}}));
  } else if (r.config.diagnose) {
    out["diagnosis"] = {{"error", r.diagnosis_status.ToString()}};
  }
  return out.dump(2) + "\n";
}

}  // namespace tpcal::pipeline
