#include "pipeline/report/diagnosis_json.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <nlohmann/json.hpp>

#include "core/xml_escape.h"
#include "pipeline/report/diagnosis_html_blocks.h"
#include "pipeline/report/json_util.h"
#include "pipeline/report/reference_agreement_report.h"
#include "pipeline/report/screen_json.h"

namespace tpcal::pipeline {
namespace {

using json = nlohmann::ordered_json;

json GroupsJson(const std::vector<GroupGap>& groups, const char* key) {
  json a = json::array();
  for (const auto& g : groups)
    a.push_back({{key, g.group}, {"rms_um", g.rms_um}, {"max_abs_um", g.max_abs_um}, {"n_points", g.n_points},
                 {"mean_um", g.mean_um}, {"mean_t_s", g.mean_t_s}, {"z", g.z}, {"stands_out", g.stands_out}});
  return a;
}

json ParametersJson(const std::vector<EffectParameter>& ps) {
  json o = json::object();
  for (const auto& p : ps) {
    // A parameter the data cannot separate gets no number (null), and says so.
    json e = {{"value", OrNull(p.identifiable, p.value)}, {"u", OrNull(p.identifiable, p.u)}, {"unit", p.unit}};
    if (!p.identifiable) e["identifiable"] = false;
    o[p.name] = e;
  }
  return o;
}

}  // namespace

std::string DiagnosisJson(const DiagnosisResult& r, const std::map<std::string, std::string>& inputs) {
  return DiagnosisJsonValue(r, inputs).dump(2) + "\n";
}

nlohmann::ordered_json DiagnosisJsonValue(const DiagnosisResult& r, const std::map<std::string, std::string>& inputs) {
  json j;
  j["schema"] = "tpcal.diagnosis/1";
  j["base_model"] = r.base_model;
  json gap;
  gap["rms_um"] = r.rms_um;
  if (r.reference_held_rms_um) gap["reference_held_rms_um"] = *r.reference_held_rms_um;
  gap["max_abs_um"] = r.max_abs_um;
  gap["n_points"] = r.n_points;
  gap["by_feature"] = GroupsJson(r.by_feature, "feature");
  gap["by_operation"] = GroupsJson(r.by_operation, "operation");
  gap["by_a_index"] = GroupsJson(r.by_a_index, "index");
  gap["drift_um_per_h"] = {{"value", r.drift_um_per_h}, {"u", r.drift_u_um_per_h}};
  json harmonics = json::array();
  for (const auto& h : r.harmonics)
    harmonics.push_back({{"feature", h.feature}, {"order", h.order}, {"amplitude_um", h.amplitude_um},
                         {"phase_deg", h.phase_deg}, {"z", h.z}, {"stands_out", h.stands_out}});
  gap["harmonics"] = harmonics;
  gap["noise_sigma_um"] = r.noise_sigma_um;
  gap["standing_out"] = r.standing_out;
  j["gap"] = gap;
  j["cross_validation"] = {{"method", "leave-one-feature-out"},
                           {"base_cv_rms_um", r.cv_rms_um},
                           {"base_press_rms_um", r.press_rms_um},
                           {"n_features", r.n_features},
                           {"features_held_out", r.cv_features},
                           {"not_held_out", r.cv_not_held_out},
                           {"not_held_out_reason",
                            "the feature's points alone determine a direction of the base model and re-alignment: "
                            "the fit without it cannot predict it"}};
  if (r.reference_match)
    j["reference_match"] = {{"matched_by_order", r.reference_match->matched_by_order},
                            {"matched_by_nearest", r.reference_match->matched_by_nearest},
                            {"max_offset_mm", r.reference_match->max_offset_mm},
                            {"unmatched", r.reference_match->unmatched}};
  json cands = json::array();
  for (const auto& c : r.candidates) {
    json e;
    e["family"] = c.family;
    e["name"] = c.name;
    e["rms_after_um"] = c.rms_after_um;
    e["shrink_pct"] = c.shrink_pct;
    e["cv_rms_before_um"] = c.cv_rms_before_um;
    e["cv_rms_after_um"] = c.cv_rms_after_um;
    e["parameters"] = ParametersJson(c.parameters);
    e["max_abs_after_um"] = c.max_abs_after_um;
    e["cv_shrink_pct"] = c.cv_shrink_pct;
    e["cv_method"] = c.cv_method;
    if (!c.cv_method_reason.empty()) e["cv_method_reason"] = c.cv_method_reason;
    e["cv_features"] = c.cv_features;
    e["cv_not_held_out"] = c.cv_not_held_out;
    e["press_rms_before_um"] = c.press_rms_before_um;
    e["press_rms_after_um"] = c.press_rms_after_um;
    e["observable"] = c.observable;
    e["n_parameters"] = c.n_columns;
    e["rank"] = c.rank;
    e["visible_share_pct"] = 100.0 * c.visible_share;
    e["typical_visible_share_pct"] = 100.0 * c.typical_visible_share;
    e["f_stat"] = c.f_stat;
    e["p_value"] = c.p_value;
    e["delta_bic"] = c.delta_bic;
    e["significant"] = c.significant;
    json shift = json::array();
    for (const auto& s : c.base_shift)
      shift.push_back({{"name", s.name}, {"unit", s.unit}, {"without", s.without_um}, {"with", s.with_um},
                       {"change", s.with_um - s.without_um}, {"u_without", s.u_without}, {"u_with", s.u_with}});
    e["base_shift"] = shift;
    cands.push_back(e);
  }
  j["candidates"] = cands;
  json v;
  v["family"] = r.verdict.family;
  v["name"] = r.verdict.name;
  v["shrink_pct"] = r.verdict.shrink_pct;
  v["indistinguishable_from"] = r.verdict.indistinguishable_from;
  v["indistinguishable_candidates"] = r.verdict.indistinguishable_candidates;
  v["cv_shrink_pct"] = r.verdict.cv_shrink_pct;
  if (r.verdict.also) v["also"] = *r.verdict.also, v["also_indistinguishable_from"] = r.verdict.also_indistinguishable_from;
  v["families"] = r.verdict.families;
  if (!r.verdict.partial.empty()) v["partial"] = r.verdict.partial;
  j["verdict"] = v;
  j["outliers"] = OutliersJson(r.outliers);
  j["local_defects"] = LocalDefectsJson(r.local_defects);
  if (!r.explained_patches.empty()) j["explained_patches"] = LocalDefectsJson(r.explained_patches);
  j["neighbour_sigma_um"] = r.neighbour_sigma_um;
  j["excess_p_value"] = r.excess_p_value;
  if (r.pair) {
    const PairFit& p = *r.pair;
    json pj;
    pj["families"] = p.families;
    pj["names"] = p.names;
    pj["why"] = p.why;
    pj["rank"] = p.rank;
    pj["rms_after_um"] = p.rms_after_um;
    pj["shrink_pct"] = p.shrink_pct;
    pj["cv_method"] = p.cv_method;
    pj["cv_rms_before_um"] = p.cv_rms_before_um;
    pj["cv_rms_after_um"] = p.cv_rms_after_um;
    pj["cv_shrink_pct"] = p.cv_shrink_pct;
    pj["p_value_beyond_verdict"] = p.p_value_beyond_verdict;
    pj["parameters"] = ParametersJson(p.parameters);
    j["pair"] = pj;
  }
  json un = json::array();
  for (const auto& u : r.unobservable) un.push_back({{"family", u.family}, {"reason", u.reason}});
  j["unobservable"] = un;
  json weak = json::array();
  for (const auto& w : r.weakly_observable)
    weak.push_back({{"family", w.family}, {"visible_share_pct", 100.0 * w.visible_share}});
  j["weakly_observable"] = weak;
  j["base_parameters"] = ParametersJson(r.base_parameters);
  j["skipped_points"] = r.skipped_points;
  if (r.reference_agreement) j["reference_agreement"] = ReferenceAgreementJson(*r.reference_agreement);
  if (!inputs.empty()) {
    json in = json::object();
    for (const auto& [k, val] : inputs) in[k] = val;
    j["inputs"] = in;
  }
  return j;
}

std::string DiagnosisText(const DiagnosisResult& r) {
  std::string o;
  o += fmt::format("base model: {}\n", r.base_model);
  o += fmt::format("gap: rms {:.3f} um, max |gap| {:.3f} um over {} points; noise sigma {:.3f} um; "
                   "drift with time {:+.3f} +- {:.3f} um/h\n",
                   r.rms_um, r.max_abs_um, r.n_points, r.noise_sigma_um, r.drift_um_per_h, r.drift_u_um_per_h);
  if (r.reference_held_rms_um)
    o += fmt::format("gap with the reference held entirely (re-alignment only): rms {:.3f} um; the parameters refitted "
                     "on top of it (base model) take it to {:.3f} um\n",
                     *r.reference_held_rms_um, r.rms_um);
  if (r.reference_match)
    o += fmt::format("reference points matched: {} by order within their feature, {} by nearest nominal position "
                     "(largest offset {:.3f} mm), {} measured point(s) without a reference point\n",
                     r.reference_match->matched_by_order, r.reference_match->matched_by_nearest,
                     r.reference_match->max_offset_mm, r.reference_match->unmatched);
  o += fmt::format("cross-validation: leave one feature out, {} of {} features held out; base model CV rms {:.3f} um "
                   "(leave-one-point-out PRESS {:.3f} um)\n",
                   r.cv_features, r.n_features, r.cv_rms_um, r.press_rms_um);
  if (!r.cv_not_held_out.empty())
    o += fmt::format("  not held out (their points alone fix a direction of the base model): {}\n",
                     fmt::join(r.cv_not_held_out, " "));
  if (r.standing_out.empty()) {
    o += "no group stands out beyond noise\n";
  } else {
    o += "standing out beyond noise:";
    for (const auto& s : r.standing_out) o += " [" + s + "]";
    o += "\n";
  }
  o += fmt::format("\n{:<20} {:<62} {:>5} {:>9} {:>8} {:>9} {:>9} {:>5} {:>9} {:>9} {}\n", "family", "candidate", "rank",
                   "rms_after", "shrink%", "cv_before", "cv_after", "cv_ft", "press_aft", "p", "");
  for (const auto& c : r.candidates) {
    o += fmt::format("{:<20} {:<62.62} {:>5} {:>9.3f} {:>8.1f} {:>9.3f} {:>9.3f} {:>5} {:>9.3f} {:>9.2g} {}\n", c.family,
                     c.name, c.rank, c.rms_after_um, c.shrink_pct, c.cv_rms_before_um, c.cv_rms_after_um, c.cv_method == "leave-one-feature-out" ? fmt::format("{}", c.cv_features) : std::string("pt"),
                     c.press_rms_after_um, c.p_value, c.significant ? "*" : (c.observable ? "" : "unobservable"));
  }
  o += "(cv_* leave one feature out over the cv_ft features the base and the candidate's fit hold out, or leave one "
       "point out (pt) when no held-out feature carries the effect or the effect makes one of the base's held-out "
       "features unholdable; press_aft leave one point out; pt candidates are ranked against the others by PRESS)\n";
  o += fmt::format("\nverdict: {} ({}), shrink {:.1f} % in-sample, {:.1f} % cross-validated\n", r.verdict.family,
                   r.verdict.name, r.verdict.shrink_pct, r.verdict.cv_shrink_pct);
  if (!r.verdict.indistinguishable_from.empty()) {
    o += "  cannot be told apart on this piece and plan from:";
    for (const auto& f : r.verdict.indistinguishable_from) o += " " + f;
    o += "\n";
  }
  for (const auto& p : r.explained_patches) o += "  a patch the screen flagged, explained by it (kept): " + PatchText(p) + "\n";
  if (const auto same = SameFamilyAlternatives(r); !same.empty())
    o += fmt::format("  within its family, explained about as well by: {}\n", fmt::join(same, "; "));
  if (r.verdict.also) {
    o += "  a second effect adds beyond it: " + *r.verdict.also;
    if (!r.verdict.also_indistinguishable_from.empty())
      o += fmt::format(" (cannot be told apart on this piece and plan from: {})", fmt::join(r.verdict.also_indistinguishable_from, " "));
    o += "\n";
  }
  if (r.pair)
    o += fmt::format("  with {} fitted jointly ({}): shrink {:.1f} % in-sample, {:.1f} % cross-validated ({}); "
                     "p = {:.3g} for the second given the first\n",
                     r.pair->names.back(), r.pair->why, r.pair->shrink_pct, r.pair->cv_shrink_pct, r.pair->cv_method,
                     r.pair->p_value_beyond_verdict);
  for (const auto& pt : r.verdict.partial) o += "  explains part of it: " + pt + "\n";
  o += ScreenText(r.outliers, r.local_defects, r.neighbour_sigma_um);
  if (IsCatalogueFamily(r.verdict.family) && !r.candidates.empty()) {
    const auto& best = r.candidates.front();
    o += "  parameters:\n";
    for (const auto& p : best.parameters)
      o += p.identifiable ? fmt::format("    {:<28} {:>10.4g} +- {:<10.3g} {}\n", p.name, p.value, p.u, p.unit)
                          : fmt::format("    {:<28} {:>10} not identifiable alone\n", p.name, "-");
    if (best.cv_method != "leave-one-feature-out")
      o += fmt::format("  cross-validated by {} ({}); not held out with this effect: {}\n", best.cv_method,
                       best.cv_method_reason, fmt::join(best.cv_not_held_out, " "));
    if (!best.base_shift.empty()) {
      o += "  change of the identified machine errors when it is modelled (value +- u without -> with):\n";
      for (const auto& s : best.base_shift)
        o += fmt::format("    {:<16} {:>9.3f} +- {:<7.3f} -> {:>9.3f} +- {:<7.3f} {}\n", s.name, s.without_um,
                         s.u_without, s.with_um, s.u_with, s.unit);
    }
  }
  for (const auto& u : r.unobservable) o += "unobservable: " + u.family + ": " + u.reason + "\n";
  for (const auto& w : r.weakly_observable)
    o += fmt::format("weakly observable: {}: {:.1f} % of a typical signature lies outside the base model on this piece "
                     "and plan (the rest is taken for location errors): an effect must be about {:.0f}x the noise "
                     "before 1x of it shows\n",
                     w.family, 100.0 * w.visible_share, w.visible_share > 0 ? 1.0 / w.visible_share : 0.0);
  if (!r.skipped_points.empty())
    o += fmt::format("{} point(s) skipped (no cut of their feature reaches them), first: {}\n", r.skipped_points.size(),
                     r.skipped_points.front());
  if (r.reference_agreement) o += ReferenceAgreementText(*r.reference_agreement);
  return o;
}

std::string DiagnosisHtml(const DiagnosisResult& r, const std::string& title) {
  std::string o = "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" + XmlEscape(title) +
                  "</title><style>body{font-family:sans-serif}table{border-collapse:collapse}td,th{border:1px "
                  "solid #999;padding:2px 6px;text-align:right}td.l{text-align:left}.hi{background:#fdd}</style>"
                  "</head><body>\n<h1>" + XmlEscape(title) + "</h1>\n";
  o += "<h2>Verdict</h2><p><b>" + XmlEscape(r.verdict.family) + "</b>: " + XmlEscape(r.verdict.name) +
       fmt::format(" (shrink {:.1f} % in-sample, {:.1f} % cross-validated)", r.verdict.shrink_pct, r.verdict.cv_shrink_pct) +
       "</p>\n";
  if (!r.verdict.indistinguishable_from.empty()) {
    o += "<p>Cannot be told apart on this piece and plan from:";
    for (const auto& f : r.verdict.indistinguishable_from) o += " " + XmlEscape(f);
    o += "</p>\n";
  }
  if (const auto same = SameFamilyAlternatives(r); !same.empty())
    o += "<p>Within its family, explained about as well by: " + XmlEscape(fmt::format("{}", fmt::join(same, "; "))) +
         "</p>\n";
  o += VerdictFamiliesHtml(r.verdict) + BaseShiftHtml(r) + ScreenHtml(r);
  if (r.reference_agreement) o += ReferenceAgreementHtml(*r.reference_agreement);
  o += "<h2>Gap</h2><pre>" + XmlEscape(DiagnosisText(r)) + "</pre>\n";
  o += "<h2>Gap by feature</h2><table><tr><th>feature</th><th>n</th><th>rms um</th><th>max um</th><th>mean um</th><th>z</th></tr>\n";
  for (const auto& g : r.by_feature)
    o += fmt::format("<tr{}><td class=l>{}</td><td>{}</td><td>{:.3f}</td><td>{:.3f}</td><td>{:.3f}</td><td>{:.1f}</td></tr>\n",
                     g.stands_out ? " class=hi" : "", XmlEscape(g.group), g.n_points, g.rms_um, g.max_abs_um, g.mean_um, g.z);
  o += "</table>\n</body></html>\n";
  return o;
}

}  // namespace tpcal::pipeline
