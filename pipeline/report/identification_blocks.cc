#include "pipeline/report/identification_blocks.h"

#include <map>
#include <string>

#include "pipeline/report/json_util.h"

namespace tpcal::pipeline {
namespace {

using Json = nlohmann::ordered_json;

Json Interval(double lo, double hi) { return Json::array({lo, hi}); }

}  // namespace

Json ParameterEstimateJson(const kinematics::ParameterEstimate& p) {
  Json j;
  j["name"] = p.name;
  j["iso_symbol"] = p.iso_symbol;
  j["identifiable"] = p.identifiable;
  j["unit"] = p.unit;
  j["value"] = OrNull(p.identifiable, p.value);
  j["u"] = OrNull(p.identifiable, p.u);
  j["ci95"] = OrNull(p.identifiable, Interval(p.ci95_low, p.ci95_high));
  Json u = Json::object();
  for (const auto& m : p.uncertainties) {
    Json e;
    const bool known = m.available && p.identifiable;
    e["u"] = OrNull(known, m.u);
    e["ci95"] = OrNull(known, Interval(m.ci95_low, m.ci95_high));
    if (!m.message.empty()) e["message"] = m.message;
    u[kinematics::UncertaintyMethodName(m.method)] = e;
  }
  j["uncertainty"] = u;
  return j;
}

Json IdentifiabilityJson(const kinematics::IdentificationResult& id) {
  return IdentifiabilityJson(id.identifiability, id.parameters);
}

Json IdentifiabilityJson(const kinematics::Identifiability& ident, const std::vector<kinematics::ParameterEstimate>& parameters) {
  std::map<std::string, std::string> unit_of;
  for (const auto& p : parameters) unit_of[p.name] = p.unit;
  Json idj;
  idj["num_parameters"] = ident.num_parameters;
  idj["rank"] = ident.rank;
  idj["condition_number"] = ident.condition_number;
  idj["singular_values"] = ident.singular_values;
  idj["not_identifiable"] = ident.not_identifiable;
  Json est = Json::array();
  for (const auto& c : ident.estimable) {
    Json e;
    e["combination"] = c.text;
    e["names"] = c.names;
    e["coefficients"] = c.coefficients;
    e["value"] = c.value;
    e["u"] = c.u;
    e["unit"] = c.names.empty() ? std::string() : unit_of[c.names.front()];
    est.push_back(std::move(e));
  }
  idj["estimable"] = std::move(est);
  Json nul = Json::array();
  for (const auto& c : ident.null_directions) nul.push_back(c.text);
  idj["null_directions"] = std::move(nul);
  return idj;
}

Json IdentificationFitJson(const kinematics::IdentificationResult& id) {
  return {{"rms_before_um", id.rms_before_um}, {"rms_after_um", id.rms_after_um},
          {"sigma_um", id.sigma_um},           {"iterations", id.iterations},
          {"termination", id.termination}};
}

}  // namespace tpcal::pipeline
