#include "pipeline/report/datum_ball_json.h"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "pipeline/report/identification_blocks.h"

namespace tpcal::pipeline {

using Json = nlohmann::ordered_json;

std::string DatumBallJson(const DatumBallReport& report) {
  const auto& r = report.result;
  Json j;
  j["schema"] = "tpcal.identification/1";
  j["instrument"] = "datum_ball";
  j["machine"] = report.machine;
  j["points_source"] = report.source;
  j["n_points"] = r.residuals_um.size();
  j["solver"] = "Gauss-Newton on the centring commands through the kinematic chain; ball centre fitted as a nuisance "
                "unless given";
  Json params = Json::array();
  for (const auto& p : r.parameters) params.push_back(ParameterEstimateJson(p));
  j["parameters"] = std::move(params);
  j["identifiability"] = IdentifiabilityJson(r.identifiability, r.parameters);
  Json cov = Json::array();
  for (Eigen::Index i = 0; i < r.covariance.rows(); ++i) {
    Json row = Json::array();
    for (Eigen::Index k = 0; k < r.covariance.cols(); ++k) row.push_back(r.covariance(i, k));
    cov.push_back(std::move(row));
  }
  j["parameter_covariance"] = std::move(cov);
  j["fit"] = {{"rms_before_um", r.rms_before_um},
              {"rms_after_um", r.rms_after_um},
              {"sigma_um", r.sigma_um},
              {"weights", r.weighted ? "u_um" : "none"},
              {"chi_scale", r.weighted ? Json(r.chi_scale) : Json(nullptr)},
              {"monte_carlo_runs", r.monte_carlo_runs},
              {"iterations", r.iterations}};
  j["ball"] = {{"centre_part_mm", {r.ball_part_mm.x(), r.ball_part_mm.y(), r.ball_part_mm.z()}},
               {"u_um", {r.ball_u_um.x(), r.ball_u_um.y(), r.ball_u_um.z()}},
               {"given", report.ball_given}};
  Json res = Json::array();
  for (std::size_t i = 0; i < r.residuals_um.size(); ++i)
    res.push_back({{"line", i < report.lines.size() ? report.lines[i] : 0},
                   {"residual_um", {r.residuals_um[i].x(), r.residuals_um[i].y(), r.residuals_um[i].z()}}});
  j["residuals"] = std::move(res);
  return j.dump(2) + "\n";
}

std::string DatumBallText(const DatumBallReport& report) {
  const auto& r = report.result;
  std::string o = fmt::format("datum ball: {} readings from {} ({}); residual RMS {:.3f} um (before {:.3f} um), sigma "
                              "{:.3f} um\n",
                              r.residuals_um.size(), report.source, report.machine, r.rms_after_um, r.rms_before_um,
                              r.sigma_um);
  if (r.weighted)
    o += fmt::format("weighted by each reading's u_um: chi-like scale {:.3f} (1 when the u_um are right; the analytic u "
                     "are scaled by it)\n",
                     r.chi_scale);
  if (r.monte_carlo_runs > 0) o += fmt::format("monte_carlo: {} re-identifications of re-simulated readings\n", r.monte_carlo_runs);
  for (const auto& p : r.parameters) {
    if (!p.identifiable) {
      o += fmt::format("  {:<12} not identifiable by this plan\n", p.name);
      continue;
    }
    o += fmt::format("  {:<12} {:>10.3f} +- {:<8.3f} {}", p.name, p.value, p.u, p.unit);
    for (const auto& u : p.uncertainties)
      if (u.method != kinematics::UncertaintyMethod::kAnalytic && u.available)
        o += fmt::format("  ({}: {:.3f})", kinematics::UncertaintyMethodName(u.method), u.u);
    o += "\n";
  }
  for (const auto& c : r.identifiability.estimable)
    o += fmt::format("  only the combination {} = {:.3f} +- {:.3f} is determined\n", c.text, c.value, c.u);
  o += fmt::format("ball centre (part frame): ({:.4f}, {:.4f}, {:.4f}) mm, ", r.ball_part_mm.x(), r.ball_part_mm.y(),
                   r.ball_part_mm.z());
  o += report.ball_given ? std::string("given\n")
                         : fmt::format("fitted (u {:.3f}, {:.3f}, {:.3f} um)\n", r.ball_u_um.x(), r.ball_u_um.y(),
                                       r.ball_u_um.z());
  return o;
}

}  // namespace tpcal::pipeline
