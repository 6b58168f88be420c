#include "pipeline/report/report_html.h"

#include <fmt/format.h>

#include <cmath>

#include "core/units.h"
#include "core/xml_escape.h"
#include "pipeline/report/diagnosis_html_blocks.h"
#include "pipeline/report/reference_agreement_report.h"
#include "pipeline/report/svg_writer.h"
#include "pipeline/version.h"

namespace tpcal::pipeline {
namespace {

constexpr const char* kReportCss = R"(body{font-family:sans-serif;margin:24px auto;max-width:1100px;color:#222;line-height:1.35}
h1{font-size:22px;margin-bottom:4px}h2{font-size:18px;border-bottom:1px solid #ccc;padding-bottom:3px;margin-top:28px}
table{border-collapse:collapse;margin:8px 0 16px 0;font-size:13px}
th,td{border:1px solid #ccc;padding:3px 7px;text-align:right;vertical-align:top}
th{background:#f2f2f2}td.t,th.t{text-align:left}
tr.na td{color:#888;font-style:italic}
.meta{color:#555;font-size:13px}.warn{color:#a04000}
figure{margin:12px 0 24px 0}figcaption{font-size:13px;color:#444;margin-top:4px}
figure svg{max-width:100%;height:auto;border:1px solid #eee}
pre{background:#f7f7f7;padding:8px;font-size:12px;overflow-x:auto}
)";

// The self-check (see report_html.h). Kept tiny and ES5 so any browser runs it.
constexpr const char* kScript = R"(<script>
var tpcalError=null;
window.addEventListener('error',function(e){tpcalError='tpcal report: SCRIPT ERROR '+(e.message||'');document.title=tpcalError;});
document.addEventListener('DOMContentLoaded',function(){
if(tpcalError){document.title=tpcalError;return;}
var svgs=document.querySelectorAll('svg'),bad=[];
for(var i=0;i<svgs.length;i++){
var n=svgs[i].querySelectorAll('path,line,circle,polygon,polyline,text').length;
var b=svgs[i].getBoundingClientRect();
if(n<3||b.width<1||b.height<1)bad.push(svgs[i].getAttribute('data-figure')||String(i));}
var want=parseInt(document.body.getAttribute('data-figures'),10);
if(svgs.length!==want)bad.push('count '+svgs.length+' of '+want);
document.title=bad.length?'tpcal report: EMPTY FIGURE '+bad.join(' '):'tpcal report: OK ('+svgs.length+' figures)';
});
</script>
)";

std::string E(const std::string& s) { return XmlEscape(s); }

std::string F(double v, int decimals = 3) {
  if (!std::isfinite(v)) return "-";
  std::string s = fmt::format("{:.{}f}", v, decimals);
  if (s.find_first_not_of("-0.") == std::string::npos && s[0] == '-') s.erase(0, 1);
  return s;
}

std::string G(double v) { return std::isfinite(v) ? fmt::format("{:.3g}", v) : "-"; }

// A parameter value in its display unit: fixed decimals for um and urad, four significant digits
// for the coefficients of polynomial error motions (um per mm^k: 4e-4 would read 0.00).
std::string P(double v, const std::string& unit, int decimals) {
  if (unit == "um" || unit == "urad") return F(v, decimals);
  return std::isfinite(v) ? fmt::format("{:.4g}", v) : "-";
}

const kinematics::Uncertainty* Method(const kinematics::ParameterEstimate& p, kinematics::UncertaintyMethod m) {
  for (const auto& u : p.uncertainties)
    if (u.method == m) return &u;
  return nullptr;
}

std::string IdentificationTable(const RunReport& r) {
  using kinematics::UncertaintyMethod;
  const auto& id = (*r.identification);
  const bool truth = !r.truth->empty();
  std::string h;
  h += "<table id=\"identification-table\"><tr><th class=\"t\">parameter</th><th class=\"t\">ISO 230-1</th>"
       "<th class=\"t\">unit</th><th>value</th><th>u analytic</th><th>u jackknife (points)</th>"
       "<th>u jackknife (features)</th><th>u Monte Carlo</th><th>95 % interval</th><th class=\"t\">identifiable</th>";
  if (truth) h += "<th>stated truth</th><th>(value - truth) / u</th>";
  h += "</tr>\n";
  for (const auto& p : id.parameters) {
    h += p.identifiable ? "<tr>" : "<tr class=\"na\">";
    h += fmt::format("<td class=\"t\">{}</td><td class=\"t\">{}</td><td class=\"t\">{}</td>", E(p.name),
                     E(p.iso_symbol), E(p.unit));
    if (p.identifiable) {
      h += fmt::format("<td>{}</td>", P(p.value, p.unit, 2));
      for (auto m : {UncertaintyMethod::kAnalytic, UncertaintyMethod::kJackknifePoints,
                     UncertaintyMethod::kJackknifeGroups, UncertaintyMethod::kMonteCarlo}) {
        const auto* u = Method(p, m);
        const bool primary = m == r.settings.primary;
        if (u && u->available)
          h += fmt::format("<td>{}{}{}</td>", primary ? "<b>" : "", P(u->u, p.unit, 3), primary ? "</b>" : "");
        else
          h += fmt::format("<td title=\"{}\">-</td>", E(u ? u->message : std::string("not computed")));
      }
      h += fmt::format("<td>[{}, {}]</td><td class=\"t\">yes</td>", P(p.ci95_low, p.unit, 2), P(p.ci95_high, p.unit, 2));
    } else {
      h += "<td>-</td><td>-</td><td>-</td><td>-</td><td>-</td><td>-</td><td class=\"t\">no</td>";
    }
    if (truth) {
      auto it = r.truth->find(p.name);
      if (it == r.truth->end()) {
        h += "<td>-</td><td>-</td>";
      } else {
        h += fmt::format("<td>{}</td><td>{}</td>", P(it->second, p.unit, 2),
                         p.identifiable && p.u > 0 ? F((p.value - it->second) / p.u, 2) : std::string("-"));
      }
    }
    h += "</tr>\n";
  }
  h += "</table>\n";
  h += fmt::format(
      "<p class=\"meta\">u: standard uncertainty (k = 1) by each method; bold: the primary method ({}), which "
      "gives the 95 % interval. Observations: {} points in {} features; residual RMS {} um before, {} um after "
      "identification; sigma {} um; {} iterations ({}).</p>\n",
      kinematics::UncertaintyMethodName(r.settings.primary), id.num_observations, id.num_groups, F(id.rms_before_um, 3),
      F(id.rms_after_um, 3), F(id.sigma_um, 3), id.iterations, E(id.termination));
  return h;
}

std::string IdentifiabilityTable(const RunReport& r) {
  const auto& ia = (*r.identification).identifiability;
  std::string h = "<table id=\"identifiability-table\">\n";
  h += fmt::format("<tr><th class=\"t\">parameters</th><td>{}</td></tr>\n", ia.num_parameters);
  h += fmt::format("<tr><th class=\"t\">rank</th><td>{}</td></tr>\n", ia.rank);
  h += fmt::format("<tr><th class=\"t\">condition number (identifiable part, scaled)</th><td>{}</td></tr>\n",
                   G(ia.condition_number));
  std::string sv;
  for (double s : ia.singular_values) sv += (sv.empty() ? "" : ", ") + G(s);
  h += fmt::format("<tr><th class=\"t\">singular values</th><td class=\"t\">{}</td></tr>\n", sv);
  std::string ni;
  for (const auto& n : ia.not_identifiable) ni += (ni.empty() ? "" : ", ") + E(n);
  h += fmt::format("<tr><th class=\"t\">not identifiable</th><td class=\"t\">{}</td></tr>\n",
                   ni.empty() ? "none" : ni);
  h += "</table>\n";
  if (!ia.estimable.empty()) {
    h += "<p>Combinations of non-identifiable parameters that the data do determine:</p>\n"
         "<table id=\"estimable-table\"><tr><th class=\"t\">combination</th><th>value</th><th>u (analytic)</th></tr>\n";
    for (const auto& c : ia.estimable)
      h += fmt::format("<tr><td class=\"t\">{}</td><td>{}</td><td>{}</td></tr>\n", E(c.text), F(c.value, 2),
                       F(c.u, 3));
    h += "</table>\n";
  }
  if (!ia.null_directions.empty()) {
    h += "<p>Directions this piece and plan cannot see (null space):</p>\n<table id=\"null-table\">"
         "<tr><th class=\"t\">combination</th></tr>\n";
    for (const auto& c : ia.null_directions) h += fmt::format("<tr><td class=\"t\">{}</td></tr>\n", E(c.text));
    h += "</table>\n";
  }
  return h;
}

std::string FigureHtml(const Figure& f);

std::string DiagnosisSection(const RunReport& r) {
  std::string h = "<h2 id=\"diagnosis\">Gap diagnosis</h2>\n";
  if (!r.diagnosis) {
    h += fmt::format("<p class=\"warn\">The diagnosis could not be made: {}</p>\n", E(r.diagnosis_error));
    return h;
  }
  const DiagnosisResult& d = *r.diagnosis;
  const Verdict& v = d.verdict;
  const std::string cv_method = (v.family != "none" && !d.candidates.empty()) ? d.candidates.front().cv_method
                                                                               : std::string("leave-one-feature-out");
  h += fmt::format(
      "<p id=\"verdict\"><b>Verdict: {}</b> ({}): the gap shrinks by {}&nbsp;% in sample, {}&nbsp;% cross-validated "
      "({}).",
      E(v.family), E(v.name), F(v.shrink_pct, 1), F(v.cv_shrink_pct, 1), E(cv_method));
  if (!v.indistinguishable_from.empty()) {
    std::string list;
    for (const auto& f : v.indistinguishable_from) list += (list.empty() ? "" : ", ") + E(f);
    h += " Indistinguishable on this piece and plan from: " + list + ".";
  }
  if (const auto same = SameFamilyAlternatives(d); !same.empty()) {
    std::string list;
    for (const auto& n : same) list += (list.empty() ? "" : "; ") + E(n);
    h += " Within its family, explained about as well by: " + list + ".";
  }
  if (v.also) h += " Also significant beyond the verdict: " + E(*v.also) + ".";
  if (d.pair)
    h += fmt::format(" Fitted together with {} ({}): shrink {}&nbsp;% in sample, {}&nbsp;% cross-validated ({}).",
                     E(d.pair->names.back()), E(d.pair->why), F(d.pair->shrink_pct, 1), F(d.pair->cv_shrink_pct, 1),
                     E(d.pair->cv_method));
  h += "</p>\n";
  h += VerdictFamiliesHtml(v) + BaseShiftHtml(d) + ScreenHtml(d);
  if (d.reference_agreement) h += ReferenceAgreementHtml(*d.reference_agreement);
  h += fmt::format(
      "<p class=\"meta\">Base model: {} ({} columns). Gap: RMS {} um, largest {} um over {} points; noise sigma {} "
      "um; linear drift with machining time {} +- {} um/h.</p>\n",
      E(d.base_model), d.base_columns, F(d.rms_um, 3), F(d.max_abs_um, 3), d.n_points, F(d.noise_sigma_um, 3),
      F(d.drift_um_per_h, 3), F(d.drift_u_um_per_h, 3));
  if (!d.standing_out.empty()) {
    std::string list;
    for (const auto& g : d.standing_out) list += (list.empty() ? "" : ", ") + E(g);
    h += "<p>Where: groups standing out beyond noise: " + list + ".</p>\n";
  } else {
    h += "<p>Where: no feature, operation or A index stands out beyond noise.</p>\n";
  }
  h += "<table id=\"candidates-table\"><tr><th class=\"t\">family</th><th class=\"t\">candidate effect</th>"
       "<th>directions</th><th>RMS after, um</th><th>shrink %</th><th>CV shrink %</th><th>p-value</th>"
       "<th class=\"t\">significant</th></tr>\n";
  for (const auto& c : d.candidates) {
    h += c.observable ? "<tr>" : "<tr class=\"na\">";
    h += fmt::format("<td class=\"t\">{}</td><td class=\"t\">{}</td><td>{} of {}</td>", E(c.family), E(c.name),
                     c.rank, c.n_columns);
    if (c.observable)
      h += fmt::format("<td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=\"t\">{}</td>", F(c.rms_after_um, 3),
                       F(c.shrink_pct, 1), F(c.cv_shrink_pct, 1), G(c.p_value), c.significant ? "yes" : "no");
    else
      h += "<td>-</td><td>-</td><td>-</td><td>-</td><td class=\"t\">unobservable</td>";
    h += "</tr>\n";
  }
  h += "</table>\n";
  if (!d.unobservable.empty()) {
    h += "<p>Families this piece and plan cannot observe:</p><ul>\n";
    for (const auto& u : d.unobservable) h += fmt::format("<li>{}: {}</li>\n", E(u.family), E(u.reason));
    h += "</ul>\n";
  }
  if (!d.weakly_observable.empty()) {
    h += "<p>Families this piece and plan observe only weakly (most of their signature is taken for location "
         "errors):</p><ul>\n";
    for (const auto& w : d.weakly_observable)
      h += fmt::format("<li>{}: {:.1f} % of a typical signature visible</li>\n", E(w.family), 100.0 * w.visible_share);
    h += "</ul>\n";
  }
  for (const auto& f : *r.figures)
    if (f.name == "gap") h += FigureHtml(f);
  return h;
}

std::string GdtTable(const gdt::InspectionResult& inspection) {
  std::string h = "<table id=\"gdt-table\"><tr><th class=\"t\">characteristic</th><th class=\"t\">type</th>"
                  "<th class=\"t\">symbol</th><th class=\"t\">features</th><th class=\"t\">values</th></tr>\n";
  for (const auto& c : inspection.characteristics) {
    std::string features, values;
    for (const auto& f : c.features) features += (features.empty() ? "" : ", ") + E(f);
    int shown = 0;
    for (const auto& v : c.values) {
      if (c.type == gdt::CharacteristicType::kHolePattern && v.name.find('.') != std::string::npos) continue;
      values += fmt::format("{}{} = {}", shown++ ? "; " : "", E(v.name), F(v.value, v.unit == "mm" ? 4 : 2));
    }
    h += fmt::format("<tr><td class=\"t\">{}</td><td class=\"t\">{}</td><td class=\"t\">{}</td><td class=\"t\">{}</td>"
                     "<td class=\"t\">{}</td></tr>\n",
                     E(c.name), gdt::CharacteristicTypeName(c.type), E(c.symbol), features, values);
  }
  h += "</table>\n";
  h += "<table id=\"features-table\"><tr><th class=\"t\">feature</th><th class=\"t\">kind</th><th>points</th>"
       "<th>residual RMS, um</th><th>form, um</th></tr>\n";
  for (const auto& f : inspection.features) {
    std::size_t n = 0;
    double rms_mm = 0;
    std::visit([&](const auto& fit) { n = fit.n_points; rms_mm = fit.stats.rms_mm; }, f.fit);
    const auto form = f.form_mm();
    h += fmt::format("<tr><td class=\"t\">{}</td><td class=\"t\">{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                     E(f.name), gdt::FeatureKindName(f.kind), n, F(MmToUm(rms_mm), 3),
                     form ? F(MmToUm(*form), 3) : std::string("-"));
  }
  h += "</table>\n";
  return h;
}

std::string FigureHtml(const Figure& f) {
  std::string svg = f.svg;
  if (svg.rfind("<svg ", 0) == 0) svg.insert(5, "data-figure=\"" + E(f.name) + "\" ");
  return fmt::format("<figure id=\"fig-{}\">\n{}<figcaption>{}</figcaption>\n</figure>\n", E(f.name), svg,
                     E(f.caption));
}

}  // namespace

std::string ReportOkTitle(std::size_t figures) { return fmt::format("tpcal report: OK ({} figures)", figures); }

std::string RenderReportHtml(const RunReport& r) {
  const auto& id = (*r.identification);
  std::string h;
  h += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  h += "<title>tpcal report: NOT CHECKED</title>\n";
  h += fmt::format("<style>{}</style>\n", kReportCss);
  h += kScript;
  h += "</head>\n";
  h += fmt::format("<body data-figures=\"{}\">\n", r.figures->size());
  h += fmt::format("<h1>Machine-tool calibration report: {}</h1>\n", E(r.piece_name));
  h += fmt::format(
      "<p class=\"meta\">Machine: {}. Points: {} ({} points, {}, XXH64 {}). tpcal {} ({}), seed {}.</p>\n",
      E(r.machine_name), E(r.settings.points), r.input.num_points, r.input.format, r.input.digest_xxh64,
      kVersion, kGitRevision, r.settings.seed);
  if (r.scan_cells)
    h += fmt::format(
        "<p class=\"meta\">Dense scan: the {} points were pooled into {} {} (mean {:.1f} points; at "
        "most {} points, {:g} mm and {:g} deg of any axis each{}). GD&amp;T used every point; identification and "
        "diagnosis used one observation per cell, so their point counts, residuals and gaps are per cell.</p>\n",
        r.scan_cells->num_points, r.scan_cells->num_cells,
        r.scan_cells->on_grid ? "cells of a fixed grid (the file is not in scan order)" : "scan-line cells",
        r.scan_cells->mean_points_per_cell,
        r.scan_cells->max_points_per_cell, r.scan_cells->max_cell_mm, r.scan_cells->max_cell_deg,
        r.scan_cells->hit_sigma_um > 0
            ? fmt::format("; {} single hits found beyond noise inside their cells, one hit's noise {:.2f} um",
                          r.scan_cells->flagged_hits, r.scan_cells->hit_sigma_um)
            : std::string());
  if (!r.settings.truth.empty())
    h += fmt::format("<p class=\"meta\">Simulated sample: stated truth from {} (red marks, truth columns).</p>\n",
                     E(r.settings.truth));

  h += "<h2 id=\"summary\">Summary</h2>\n<ul>\n";
  int identified = 0;
  for (const auto& p : id.parameters) identified += p.identifiable ? 1 : 0;
  h += fmt::format("<li>{} of {} machine error parameters identifiable (rank {}, condition number {}).</li>\n",
                   identified, id.parameters.size(), id.identifiability.rank, G(id.identifiability.condition_number));
  h += fmt::format("<li>Residual RMS {} um before and {} um after identification ({} points, {} features).</li>\n",
                   F(id.rms_before_um, 3), F(id.rms_after_um, 3), id.num_observations, id.num_groups);
  h += fmt::format("<li>{} GD&amp;T characteristics, {} fitted features (datum frame from the measured "
                   "features).</li>\n</ul>\n",
                   (*r.inspection).characteristics.size(), (*r.inspection).features.size());

  h += "<h2 id=\"identification\">Identified machine errors</h2>\n";
  for (const auto& f : *r.figures)
    if (f.name == "machine_errors") h += FigureHtml(f);
  h += IdentificationTable(r);

  h += "<h2 id=\"identifiability\">Identifiability</h2>\n";
  h += IdentifiabilityTable(r);

  if (r.settings.diagnose) h += DiagnosisSection(r);

  h += "<h2 id=\"gdt\">GD&amp;T of the test piece</h2>\n";
  h += GdtTable((*r.inspection));
  for (const auto& f : *r.figures)
    if (f.name != "machine_errors" && f.name != "gap") h += FigureHtml(f);

  h += "<h2 id=\"config\">Effective configuration</h2>\n";
  h += fmt::format("<pre>{}</pre>\n", E(r.settings.yaml));
  h += "</body>\n</html>\n";
  return h;
}

}  // namespace tpcal::pipeline
