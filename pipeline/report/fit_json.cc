#include "pipeline/report/fit_json.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <type_traits>

#include "core/units.h"
#include "pipeline/report/json_util.h"

namespace tpcal::pipeline {
namespace {

using json = nlohmann::ordered_json;

template <typename F>
void AddStats(const fitting::FitResult<F>& r, json* j) {
  (*j)["n_points"] = r.n_points;
  (*j)["rms_um"] = MmToUm(r.stats.rms_mm);
  (*j)["form_ls_um"] = MmToUm(r.stats.form_mm);
  (*j)["sigma_um"] = MmToUm(r.stats.sigma_mm);
  (*j)["termination"] = fitting::TerminationName(r.termination);
  (*j)["iterations"] = r.iterations;
  if (r.covariance.size() > 0 && r.parameter_names.size() == static_cast<std::size_t>(r.covariance.rows())) {
    json u = json::object();
    for (std::size_t k = 0; k < r.parameter_names.size(); ++k) {
      const double var = r.covariance(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k));
      u["u_" + r.parameter_names[k]] = var > 0 ? std::sqrt(var) : 0.0;
    }
    (*j)["standard_uncertainty"] = u;
  }
}

json FeatureParameters(const gdt::FittedFeature& f) {
  json p = json::object();
  std::visit(
      [&](const auto& r) {
        using R = std::decay_t<decltype(r)>;
        const auto& g = r.feature;
        if constexpr (std::is_same_v<R, fitting::FitResult<fitting::Line2>>) {
          p["point_uv_mm"] = Vec(g.point_mm);
          p["direction_uv"] = Vec(g.direction);
        } else if constexpr (std::is_same_v<R, fitting::FitResult<fitting::Line3>>) {
          p["point_mm"] = Vec(g.point_mm);
          p["direction"] = Vec(g.direction);
        } else if constexpr (std::is_same_v<R, fitting::FitResult<fitting::Plane>>) {
          p["point_mm"] = Vec(g.point_mm);
          p["normal"] = Vec(g.normal);
        } else if constexpr (std::is_same_v<R, fitting::FitResult<fitting::Circle2>>) {
          p["center_uv_mm"] = Vec(g.center_mm);
          p["radius_mm"] = g.radius_mm;
        } else if constexpr (std::is_same_v<R, fitting::FitResult<fitting::Circle3>>) {
          p["center_mm"] = Vec(g.center_mm);
          p["axis"] = Vec(g.axis);
          p["radius_mm"] = g.radius_mm;
        } else if constexpr (std::is_same_v<R, fitting::FitResult<fitting::Cylinder>>) {
          p["point_mm"] = Vec(g.point_mm);
          p["axis"] = Vec(g.axis);
          p["radius_mm"] = g.radius_mm;
        } else if constexpr (std::is_same_v<R, fitting::FitResult<fitting::Sphere>>) {
          p["center_mm"] = Vec(g.center_mm);
          p["radius_mm"] = g.radius_mm;
        } else if constexpr (std::is_same_v<R, fitting::FitResult<fitting::Cone>>) {
          p["point_mm"] = Vec(g.point_mm);
          p["axis"] = Vec(g.axis);
          p["radius_mm"] = g.radius_mm;
          p["half_angle_deg"] = RadToDeg(g.half_angle_rad);
        } else {
          p["point_mm"] = Vec(g.point_mm);
        }
      },
      f.fit);
  return p;
}

json FeatureJson(const gdt::FittedFeature& f) {
  json j;
  j["name"] = f.name;
  j["kind"] = gdt::FeatureKindName(f.kind);
  j["criterion"] = gdt::FormCriterionName(f.criterion);
  if (f.projection != gdt::Projection::kNone) {
    j["projection"] = gdt::ProjectionName(f.projection);
    j["height_mm"] = f.height_mm;
  }
  j["parameters"] = FeatureParameters(f);
  std::visit([&](const auto& r) { AddStats(r, &j); }, f.fit);
  if (auto form = f.form_mm()) j["form_um"] = MmToUm(*form);
  if (f.form_mz) {
    j["form_mz_um"] = MmToUm(f.form_mz->width_mm);
    j["form_mz_verified"] = f.form_mz->verified_optimal;
  }
  if (!f.members.empty()) j["members"] = f.members;
  return j;
}

json CharacteristicJson(const gdt::CharacteristicResult& c) {
  json j;
  j["name"] = c.name;
  j["type"] = gdt::CharacteristicTypeName(c.type);
  if (!c.symbol.empty()) j["symbol"] = c.symbol;
  if (!c.description.empty()) j["description"] = c.description;
  j["features"] = c.features;
  if (c.criterion) j["criterion"] = gdt::FormCriterionName(*c.criterion);
  json values = json::object();
  for (const auto& v : c.values) values[v.name] = v.value;
  j["values"] = values;
  if (!c.profile.empty()) {
    json prof = json::array();
    for (const auto& s : c.profile) prof.push_back(json::array({s.theta_deg, s.dr_um}));
    j["profile_columns"] = json::array({"theta_deg", "dr_um"});
    j["profile"] = prof;
  }
  return j;
}

}  // namespace

std::string FitResultJson(const gdt::InspectionResult& result) { return FitResultJsonValue(result).dump(2) + "\n"; }

nlohmann::ordered_json FitResultJsonValue(const gdt::InspectionResult& result) {
  json j;
  j["schema"] = "tpcal.fit/1";
  j["points_source"] = result.points_source;
  if (!result.plan_source.empty()) j["plan_source"] = result.plan_source;
  if (!result.plan_name.empty()) j["plan"] = result.plan_name;
  if (result.frame_type) {
    j["datum_frame"] = {{"type", gdt::DatumFrameTypeName(*result.frame_type)},
                        {"datum_from_cmm", RigidJson(result.datum_from_cmm)}};
  } else {
    j["datum_frame"] = {{"type", "cmm"}, {"datum_from_cmm", RigidJson(result.datum_from_cmm)}};
  }
  json features = json::array();
  for (const auto& f : result.features) features.push_back(FeatureJson(f));
  j["features"] = features;
  json chars = json::array();
  for (const auto& c : result.characteristics) chars.push_back(CharacteristicJson(c));
  j["characteristics"] = std::move(chars);
  return j;
}

}  // namespace tpcal::pipeline
