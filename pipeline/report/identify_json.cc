#include "pipeline/report/identify_json.h"

#include "pipeline/report/identification_blocks.h"
#include "pipeline/report/json_util.h"
#include "pipeline/report/screen_json.h"

namespace tpcal::pipeline {
namespace {

using Json = nlohmann::ordered_json;

}  // namespace

std::string IdentificationJson(const IdentificationReport& report) {
  const auto& id = report.identification;
  Json j;
  j["schema"] = "tpcal.identification/1";
  j["testpiece"] = report.testpiece;
  j["machine"] = report.machine;
  j["points_source"] = report.points_source;
  j["n_points"] = id.num_observations;
  j["n_features"] = id.num_groups;
  j["solver"] = "point-level least squares through the kinematic chain (Ceres), 6-DOF alignment nuisance";
  Json params = Json::array();
  for (const auto& p : id.parameters) params.push_back(ParameterEstimateJson(p));
  j["parameters"] = params;

  j["identifiability"] = IdentifiabilityJson(id);
  j["fit"] = IdentificationFitJson(id);
  j["alignment"] = RigidJson(id.alignment);
  j["outliers"] = OutliersJson(report.outliers);
  j["local_defects"] = LocalDefectsJson(report.local_defects);
  j["neighbour_sigma_um"] = report.neighbour_sigma_um;
  if (report.gap_check) {
    const GapCheck& g = *report.gap_check;
    j["gap_check"] = {{"verdict", g.family},       {"families", g.families}, {"name", g.name},
                      {"cv_shrink_pct", g.cv_shrink_pct}, {"warning", g.warning}};
  }

  if (report.closed_form) {
    const auto& cf = *report.closed_form;
    Json c;
    c["equations"] = kinematics::Seed002EquationsName(cf.equations);
    c["rank"] = cf.rank;
    Json items = Json::object();
    for (const auto& [k, v] : report.items) items[k] = v;
    c["items"] = items;
    Json ps = Json::array();
    for (const auto& p : cf.parameters) {
      Json e;
      e["name"] = p.name;
      e["unit"] = p.unit;
      e["identifiable"] = p.identifiable;
      e["value"] = OrNull(p.identifiable, p.value);
      ps.push_back(e);
    }
    c["parameters"] = ps;
    c["estimable"] = cf.estimable;
    Json res = Json::object();
    for (std::size_t i = 0; i < cf.items_used.size(); ++i) res[cf.items_used[i]] = cf.item_residuals[i];
    c["item_residuals"] = res;
    j["closed_form"] = c;
  }
  Json em = Json::array();
  for (const auto& m : report.error_motion) {
    Json e;
    e["name"] = m.name;
    e["faces"] = m.faces;
    e["a_deg"] = m.a_deg;
    e["c_deg"] = m.profile.c_deg;
    e["radial_um"] = m.profile.radial_um;
    e["tilt_urad"] = m.profile.tilt_urad;
    e["radial_pv_um"] = m.profile.radial_pv_um;
    e["tilt_pv_urad"] = m.profile.tilt_pv_urad;
    em.push_back(e);
  }
  j["error_motion"] = em;
  Json st = Json::array();
  for (const auto& s : report.straightness) {
    Json e;
    e["name"] = s.name;
    e["feature"] = s.feature;
    e["moving_axis"] = s.moving_axis;
    e["direction"] = s.direction;
    e["position_mm"] = s.position_mm;
    e["deviation_um"] = s.deviation_um;
    e["pv_ls_um"] = s.pv_ls_um;
    e["mz_um"] = s.mz_um;
    e["mz_certified"] = s.mz_certified;
    e["slope_urad"] = s.slope_urad;
    st.push_back(e);
  }
  j["straightness"] = st;
  return j.dump(2) + "\n";
}

}  // namespace tpcal::pipeline
