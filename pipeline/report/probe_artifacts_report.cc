#include "pipeline/report/probe_artifacts_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <utility>

#include "core/xml_escape.h"
#include "pipeline/report/json_util.h"
#include "pipeline/report/svg_writer.h"

namespace tpcal::pipeline {
namespace {

using PaJson = nlohmann::ordered_json;
using kinematics::ErrorMapEntry;
using kinematics::TablePose;
using kinematics::TablePoseFit;

// Positions within this of each other are the same node (the fit groups touches the same way).
constexpr double kPaSameDeg = 1e-6;

// Standard uncertainty (k = 1) of component `c` of pose `p`: sqrt of the covariance diagonal
// (6 x poses, pose order); 0 where the covariance does not hold it.
double PaPoseU(const TablePoseFit& fit, std::size_t p, int c) {
  const Eigen::Index i = static_cast<Eigen::Index>(6 * p) + c;
  if (i >= fit.covariance.rows() || i >= fit.covariance.cols()) return 0.0;
  return std::sqrt(std::max(0.0, fit.covariance(i, i)));
}

// The map symbols in entry order ("E_XA" .. "E_CC").
std::vector<std::string> PaSymbols(const kinematics::ErrorMaps& maps) {
  std::vector<std::string> out;
  for (const ErrorMapEntry& e : maps.entries)
    if (std::find(out.begin(), out.end(), e.symbol) == out.end()) out.push_back(e.symbol);
  return out;
}

std::vector<const ErrorMapEntry*> PaEntriesOf(const kinematics::ErrorMaps& maps, const std::string& symbol) {
  std::vector<const ErrorMapEntry*> out;
  for (const ErrorMapEntry& e : maps.entries)
    if (e.symbol == symbol) out.push_back(&e);
  return out;
}

const ErrorMapEntry* PaFindEntry(const std::vector<const ErrorMapEntry*>& entries, double a_deg, double c_deg) {
  for (const ErrorMapEntry* e : entries)
    if (std::abs(e->a_deg - a_deg) < kPaSameDeg && (!e->c_map || std::abs(e->c_deg - c_deg) < kPaSameDeg)) return e;
  return nullptr;
}

const TablePose* PaReferencePose(const TablePoseFit& fit) {
  for (const TablePose& p : fit.poses)
    if (p.reference) return &p;
  return nullptr;
}

std::string PaArtifactName(const ProbeArtifactsReport& report, int index) {
  if (index >= 0 && static_cast<std::size_t>(index) < report.artifacts.boxes.size())
    return report.artifacts.boxes[static_cast<std::size_t>(index)].name;
  return std::to_string(index);
}

// "1.234 +- 0.012" or "-" (not identifiable).
std::string PaValueU(bool identifiable, double value, double u) {
  return identifiable ? fmt::format("{:.3f} +- {:.3f}", value, u) : std::string("-");
}

// Text lines naming what the touches cannot determine: pose components, then map entries.
std::vector<std::string> PaNotIdentifiableLines(const ProbeArtifactsReport& report) {
  std::vector<std::string> out;
  const TablePoseFit& fit = report.result.poses;
  for (double a : fit.a_deg)
    for (double c : fit.c_deg)
      if (std::none_of(fit.poses.begin(), fit.poses.end(), [&](const TablePose& p) {
            return std::abs(p.a_deg - a) < kPaSameDeg && std::abs(p.c_deg - c) < kPaSameDeg;
          }))
        out.push_back(fmt::format("position A {:g} deg, C {:g} deg: no touches", a, c));
  for (const TablePose& p : fit.poses)
    for (int c = 0; c < 6; ++c)
      if (!p.identifiable[static_cast<std::size_t>(c)])
        out.push_back(fmt::format("pose {} at A {:g} deg, C {:g} deg", kinematics::kPoseComponents[c], p.a_deg,
                                  p.c_deg));
  for (const auto& f : report.result.poses.faces)
    if (!f.identifiable)
      out.push_back(fmt::format("face offset {} {}", PaArtifactName(report, f.artifact), kinematics::BoxFaceName(f.face)));
  for (const std::string& s : report.result.maps.not_identifiable) out.push_back(s);
  return out;
}

// ---------- JSON ----------

PaJson PaArtifactsJson(const kinematics::ArtifactSet& set) {
  PaJson a = PaJson::array();
  for (const auto& b : set.boxes)
    a.push_back({{"name", b.name},
                 {"base_centre_mm", Vec(b.base_centre_mm)},
                 {"size_mm", Vec(b.size_mm)},
                 {"rotation_deg", b.rotation_deg}});
  return a;
}

// The 6 x 6 covariance block of pose `p` (um^2, um urad, urad^2; k = 1), rows and columns in
// kPoseComponents order; null where either component is not identifiable (no number to correlate).
PaJson PaPoseCovarianceJson(const TablePoseFit& fit, std::size_t p) {
  const TablePose& pose = fit.poses[p];
  const Eigen::Index base = static_cast<Eigen::Index>(6 * p);
  PaJson rows = PaJson::array();
  for (int r = 0; r < 6; ++r) {
    PaJson row = PaJson::array();
    for (int c = 0; c < 6; ++c) {
      const bool ok = pose.identifiable[static_cast<std::size_t>(r)] && pose.identifiable[static_cast<std::size_t>(c)] &&
                      base + 5 < fit.covariance.rows() && base + 5 < fit.covariance.cols();
      row.push_back(OrNull(ok, ok ? fit.covariance(base + r, base + c) : 0.0));
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

PaJson PaPosesJson(const TablePoseFit& fit) {
  PaJson poses = PaJson::array();
  for (std::size_t p = 0; p < fit.poses.size(); ++p) {
    const TablePose& pose = fit.poses[p];
    PaJson j = {{"a_deg", pose.a_deg}, {"c_deg", pose.c_deg}, {"reference", pose.reference}, {"touches", pose.touches}};
    for (int c = 0; c < 6; ++c) {
      const bool ok = pose.identifiable[static_cast<std::size_t>(c)];
      j[kinematics::kPoseComponents[c]] = {{"value", OrNull(ok, pose.value(c))},
                                           {"unit", kinematics::kPoseUnits[c]},
                                           {"identifiable", ok},
                                           {"u", OrNull(ok, PaPoseU(fit, p, c))}};
    }
    j["covariance"] = PaPoseCovarianceJson(fit, p);
    poses.push_back(std::move(j));
  }
  return poses;
}

PaJson PaFacesJson(const ProbeArtifactsReport& report) {
  PaJson faces = PaJson::array();
  for (const auto& f : report.result.poses.faces)
    faces.push_back({{"artifact", PaArtifactName(report, f.artifact)},
                     {"face", kinematics::BoxFaceName(f.face)},
                     {"touches", f.touches},
                     {"value_um", OrNull(f.identifiable, f.value_um)},
                     {"u_um", OrNull(f.identifiable, f.u_um)},
                     {"identifiable", f.identifiable}});
  return faces;
}

// The linear axes' errors fitted with the poses, as identify's "parameters" (tpcal.identification/1).
PaJson PaLinearErrorsJson(const TablePoseFit& fit) {
  PaJson out = PaJson::array();
  for (const kinematics::ParameterEstimate& e : fit.linear_errors)
    out.push_back({{"name", e.name},
                   {"unit", e.unit},
                   {"identifiable", e.identifiable},
                   {"value", OrNull(e.identifiable, e.value)},
                   {"u", OrNull(e.identifiable, e.u)},
                   {"ci95", e.identifiable ? PaJson{e.ci95_low, e.ci95_high} : PaJson(nullptr)}});
  return out;
}

// "linear axes' errors fitted with the poses, value +- u (k=1): E_C(0X)Y 1.234 +- 0.567 urad, ...".
std::string PaLinearErrorsLine(const TablePoseFit& fit) {
  if (fit.linear_errors.empty()) return "linear axes taken as error-free (no squareness fitted)\n";
  std::string o = "linear axes' errors fitted with the poses, value +- u (k=1):";
  for (const kinematics::ParameterEstimate& e : fit.linear_errors)
    o += fmt::format(" {} {} {};", e.name, PaValueU(e.identifiable, e.value, e.u), e.unit);
  o.back() = '\n';
  return o;
}

PaJson PaMapsJson(const kinematics::ErrorMaps& maps) {
  PaJson out = PaJson::array();
  for (const ErrorMapEntry& e : maps.entries) {
    PaJson j = {{"symbol", e.symbol}, {"coefficient", e.coefficient}, {"unit", e.unit}, {"a_deg", e.a_deg}};
    if (e.c_map) j["c_deg"] = e.c_deg;
    j["identifiable"] = e.identifiable;
    j["value"] = OrNull(e.identifiable, e.value);
    j["u"] = OrNull(e.identifiable, e.u);
    j["ci95"] = e.identifiable ? PaJson{e.ci95_low, e.ci95_high} : PaJson(nullptr);
    out.push_back(std::move(j));
  }
  return out;
}

// ---------- text and HTML tables ----------

std::string PaHeaderLine(const ProbeArtifactsReport& report) {
  const TablePoseFit& f = report.result.poses;
  std::string o = fmt::format("probe artifacts: {} touches from {} ({}); artifacts {} ({} boxes); stylus radius {:g} mm\n",
                              f.num_touches, report.source, report.machine,
                              report.artifacts_source.empty() ? std::string("seed 000 default set")
                                                              : report.artifacts_source,
                              report.artifacts.boxes.size(), report.probe_radius_mm);
  o += fmt::format("fit: {} table poses, rank {}, dof {}, sigma {:.3f} um", f.poses.size(), f.rank, f.dof, f.sigma_um);
  if (f.weighted) o += fmt::format(", weighted by each touch's u_um: chi-like scale {:.3f}", f.chi_scale);
  return o + "\n" + PaLinearErrorsLine(f);
}

// The 12 maps' block for one symbol: A maps one row per A; C maps one row per A, columns C.
std::string PaMapText(const kinematics::ErrorMaps& maps, const std::string& symbol) {
  const auto entries = PaEntriesOf(maps, symbol);
  if (entries.empty()) return "";
  const bool c_map = entries.front()->c_map;
  const std::string& unit = entries.front()->unit;
  std::string o;
  if (!c_map) {
    o += fmt::format("{} ({}), A-axis map, value +- u (k=1), rows A (deg):\n", symbol, unit);
    for (double a : maps.a_deg) {
      const ErrorMapEntry* e = PaFindEntry(entries, a, 0.0);
      o += fmt::format("  {:>9g} {:>18}\n", a, e ? PaValueU(e->identifiable, e->value, e->u) : "-");
    }
    return o;
  }
  o += fmt::format("{} ({}), C-axis map, value +- u (k=1), rows A (deg), columns C (deg):\n", symbol, unit);
  o += fmt::format("  {:>9}", "A \\ C");
  for (double c : maps.c_deg) o += fmt::format(" {:>18g}", c);
  o += "\n";
  for (double a : maps.a_deg) {
    o += fmt::format("  {:>9g}", a);
    for (double c : maps.c_deg) {
      const ErrorMapEntry* e = PaFindEntry(entries, a, c);
      o += fmt::format(" {:>18}", e ? PaValueU(e->identifiable, e->value, e->u) : "-");
    }
    o += "\n";
  }
  return o;
}

std::string PaPoseTableText(const TablePoseFit& fit) {
  std::string o = fmt::format("{:>7} {:>7} {:>7}", "A deg", "C deg", "touches");
  for (int c = 0; c < 6; ++c)
    o += fmt::format(" {:>18}", fmt::format("{} {}", kinematics::kPoseComponents[c], kinematics::kPoseUnits[c]));
  o += "\n";
  for (std::size_t p = 0; p < fit.poses.size(); ++p) {
    const TablePose& pose = fit.poses[p];
    o += fmt::format("{:>7g} {:>7g} {:>7}", pose.a_deg, pose.c_deg, pose.touches);
    for (int c = 0; c < 6; ++c)
      o += fmt::format(" {:>18}", PaValueU(pose.identifiable[static_cast<std::size_t>(c)], pose.value(c),
                                           PaPoseU(fit, p, c)));
    o += pose.reference ? "  (reference: zero by definition)\n" : "\n";
  }
  return o;
}

// One line per pose: its largest correlation between two identifiable components, from the pose's
// 6 x 6 covariance block (the blocks themselves are in the JSON, `poses[].covariance`).
std::string PaPoseCorrelationText(const TablePoseFit& fit) {
  std::string o;
  for (std::size_t p = 0; p < fit.poses.size(); ++p) {
    const TablePose& pose = fit.poses[p];
    if (pose.reference) continue;
    double best = 0.0;
    int best_r = -1, best_c = -1;
    for (int r = 0; r < 6; ++r)
      for (int c = r + 1; c < 6; ++c) {
        const double ur = PaPoseU(fit, p, r), uc = PaPoseU(fit, p, c);
        if (!pose.identifiable[static_cast<std::size_t>(r)] || !pose.identifiable[static_cast<std::size_t>(c)] ||
            ur <= 0.0 || uc <= 0.0)
          continue;
        const Eigen::Index i = static_cast<Eigen::Index>(6 * p);
        const double rho = fit.covariance(i + r, i + c) / (ur * uc);
        if (std::abs(rho) > std::abs(best)) best = rho, best_r = r, best_c = c;
      }
    o += fmt::format("{:>7g} {:>7g}", pose.a_deg, pose.c_deg);
    o += best_r < 0 ? std::string("  -\n")
                    : fmt::format("  {:+.3f} ({}, {})\n", best, kinematics::kPoseComponents[best_r],
                                  kinematics::kPoseComponents[best_c]);
  }
  return o;
}

std::string PaCell(const std::string& text) { return "<td>" + XmlEscape(text) + "</td>"; }

std::string PaPoseTableHtml(const TablePoseFit& fit) {
  std::string o = "<table>\n<tr><th>A deg</th><th>C deg</th><th>touches</th>";
  for (int c = 0; c < 6; ++c)
    o += fmt::format("<th>{} {}</th>", kinematics::kPoseComponents[c], kinematics::kPoseUnits[c]);
  o += "</tr>\n";
  for (std::size_t p = 0; p < fit.poses.size(); ++p) {
    const TablePose& pose = fit.poses[p];
    o += fmt::format("<tr{}>", pose.reference ? " class=\"paref\"" : "");
    o += PaCell(fmt::format("{:g}", pose.a_deg)) + PaCell(fmt::format("{:g}", pose.c_deg)) +
         PaCell(std::to_string(pose.touches));
    for (int c = 0; c < 6; ++c)
      o += PaCell(PaValueU(pose.identifiable[static_cast<std::size_t>(c)], pose.value(c), PaPoseU(fit, p, c)));
    o += "</tr>\n";
  }
  return o + "</table>\n";
}

std::string PaMapTableHtml(const kinematics::ErrorMaps& maps, const std::string& symbol) {
  const auto entries = PaEntriesOf(maps, symbol);
  if (entries.empty()) return "";
  const bool c_map = entries.front()->c_map;
  std::string o = "<table>\n<tr><th>A deg</th>";
  if (!c_map) {
    o += fmt::format("<th>{} {} (value +- u)</th></tr>\n", XmlEscape(symbol), XmlEscape(entries.front()->unit));
    for (double a : maps.a_deg) {
      const ErrorMapEntry* e = PaFindEntry(entries, a, 0.0);
      o += "<tr>" + PaCell(fmt::format("{:g}", a)) + PaCell(e ? PaValueU(e->identifiable, e->value, e->u) : "-") +
           "</tr>\n";
    }
    return o + "</table>\n";
  }
  for (double c : maps.c_deg) o += fmt::format("<th>C {:g}</th>", c);
  o += "</tr>\n";
  for (double a : maps.a_deg) {
    o += "<tr>" + PaCell(fmt::format("{:g}", a));
    for (double c : maps.c_deg) {
      const ErrorMapEntry* e = PaFindEntry(entries, a, c);
      o += PaCell(e ? PaValueU(e->identifiable, e->value, e->u) : "-");
    }
    o += "</tr>\n";
  }
  return o + "</table>\n";
}

// ---------- figures ----------

constexpr const char* kPaCss =
    ".pa-ax{stroke:#888;stroke-width:1;fill:none}.pa-grid{stroke:#e3e3e3;stroke-width:1;fill:none}"
    ".pa-zero{stroke:#444;stroke-width:1}.pa-lbl{fill:#222}.pa-sm{fill:#555;font-size:9px}"
    ".pa-ttl{fill:#000;font-size:13px;font-weight:bold}.pa-na{stroke:#999;fill:#fff;stroke-width:1}"
    ".pa-l0{stroke:#1f5fa8;fill:none;stroke-width:1.5}.pa-p0{stroke:#1f5fa8;fill:#1f5fa8}.pa-b0{fill:#1f5fa8;fill-opacity:0.15;stroke:none}"
    ".pa-l1{stroke:#c0392b;fill:none;stroke-width:1.5}.pa-p1{stroke:#c0392b;fill:#c0392b}.pa-b1{fill:#c0392b;fill-opacity:0.15;stroke:none}"
    ".pa-l2{stroke:#27864a;fill:none;stroke-width:1.5}.pa-p2{stroke:#27864a;fill:#27864a}.pa-b2{fill:#27864a;fill-opacity:0.15;stroke:none}"
    ".pa-l3{stroke:#7b3fa0;fill:none;stroke-width:1.5}.pa-p3{stroke:#7b3fa0;fill:#7b3fa0}.pa-b3{fill:#7b3fa0;fill-opacity:0.15;stroke:none}"
    ".pa-l4{stroke:#b8860b;fill:none;stroke-width:1.5}.pa-p4{stroke:#b8860b;fill:#b8860b}.pa-b4{fill:#b8860b;fill-opacity:0.15;stroke:none}"
    ".pa-l5{stroke:#444;fill:none;stroke-width:1.5}.pa-p5{stroke:#444;fill:#444}.pa-b5{fill:#444;fill-opacity:0.15;stroke:none}";
constexpr int kPaStyles = 6;

// One curve of a figure: the map's entries in angle order (A maps: over A; C maps: over C at one A).
struct PaSeries {
  std::string label;
  std::vector<const ErrorMapEntry*> entries;
};

// The error against its angle: one line per series through the identifiable nodes (broken at
// nodes without a number, drawn as hollow marks on the zero line), the 95 % band shaded.
std::string PaMapFigure(const kinematics::ErrorMaps& maps, const std::string& symbol) {
  const auto entries = PaEntriesOf(maps, symbol);
  if (entries.empty()) return "";
  const bool c_map = entries.front()->c_map;
  const std::string& unit = entries.front()->unit;
  std::vector<PaSeries> series;
  if (!c_map) {
    PaSeries s;
    for (double a : maps.a_deg)
      if (const ErrorMapEntry* e = PaFindEntry(entries, a, 0.0)) s.entries.push_back(e);
    series.push_back(std::move(s));
  } else {
    for (double a : maps.a_deg) {
      PaSeries s{fmt::format("A = {:g} deg", a), {}};
      for (double c : maps.c_deg)
        if (const ErrorMapEntry* e = PaFindEntry(entries, a, c)) s.entries.push_back(e);
      series.push_back(std::move(s));
    }
  }
  const std::vector<double>& xs = c_map ? maps.c_deg : maps.a_deg;
  double x_lo = xs.empty() ? 0.0 : *std::min_element(xs.begin(), xs.end());
  double x_hi = xs.empty() ? 1.0 : *std::max_element(xs.begin(), xs.end());
  if (x_hi - x_lo < 1e-9) x_lo -= 1.0, x_hi += 1.0;
  double y_lo = 0.0, y_hi = 0.0;
  for (const ErrorMapEntry* e : entries)
    if (e->identifiable && std::isfinite(e->ci95_low) && std::isfinite(e->ci95_high))
      y_lo = std::min(y_lo, e->ci95_low), y_hi = std::max(y_hi, e->ci95_high);
  const double y_step = NiceStep(std::max(y_hi - y_lo, 1e-3), 5);
  y_lo = std::floor(y_lo / y_step) * y_step;
  y_hi = std::ceil(y_hi / y_step) * y_step;
  if (y_hi - y_lo < y_step) y_hi = y_lo + y_step;

  const double W = 600, H = 320, left = 60, right = c_map ? 110 : 20, top = 40, bottom = 40;
  const double pw = W - left - right, ph = H - top - bottom;
  auto px = [&](double x) { return left + (x - x_lo) / (x_hi - x_lo) * pw; };
  auto py = [&](double y) { return top + (y_hi - y) / (y_hi - y_lo) * ph; };
  const char* angle = c_map ? "C" : "A";
  SvgWriter svg(W, H, fmt::format("{} over {}", symbol, angle), kPaCss);
  svg.Text(12, 16,
           fmt::format("{} ({}) over {}: identified values, shaded 95 % interval", symbol, c_map ? "C-axis map" : "A-axis map",
                       angle),
           "pa-ttl");
  for (double y = y_lo; y <= y_hi + 1e-9 * y_step; y += y_step) {
    svg.Line(left, py(y), left + pw, py(y), "pa-grid");
    svg.Text(left - 6, py(y) + 3, fmt::format("{:g}", std::abs(y) < 1e-9 * y_step ? 0.0 : y), "pa-sm", "end");
  }
  for (double x : xs) {  // ticks at the measured positions (the nodes)
    svg.Line(px(x), top, px(x), top + ph, "pa-grid");
    svg.Text(px(x), top + ph + 14, fmt::format("{:g}", x), "pa-sm", "middle");
  }
  svg.Rect(left, top, pw, ph, "pa-ax");
  if (y_lo < 0.0 && y_hi > 0.0) svg.Line(left, py(0.0), left + pw, py(0.0), "pa-zero");
  svg.Text(left + pw / 2, H - 10, fmt::format("{} (deg)", angle), "pa-lbl", "middle");
  svg.Text(left - 6, top - 6, fmt::format("{} ({})", symbol, unit), "pa-lbl", "start");

  for (std::size_t k = 0; k < series.size(); ++k) {
    const int style = static_cast<int>(k % kPaStyles);
    const PaSeries& s = series[k];
    svg.BeginGroup(fmt::format("pa-s{}", style), s.label);
    // Runs of consecutive identifiable nodes: a band and a line each.
    std::size_t i = 0;
    while (i < s.entries.size()) {
      if (!s.entries[i]->identifiable) {
        svg.Circle(px(c_map ? s.entries[i]->c_deg : s.entries[i]->a_deg), py(0.0), 3.5, "pa-na");
        ++i;
        continue;
      }
      std::size_t j = i;
      while (j < s.entries.size() && s.entries[j]->identifiable) ++j;
      std::vector<std::pair<double, double>> band, line;
      for (std::size_t m = i; m < j; ++m) {
        const ErrorMapEntry& e = *s.entries[m];
        const double x = px(c_map ? e.c_deg : e.a_deg);
        band.emplace_back(x, py(e.ci95_high));
        line.emplace_back(x, py(e.value));
      }
      for (std::size_t m = j; m-- > i;) {
        const ErrorMapEntry& e = *s.entries[m];
        band.emplace_back(px(c_map ? e.c_deg : e.a_deg), py(e.ci95_low));
      }
      svg.Polyline(band, true, fmt::format("pa-b{}", style));
      if (line.size() > 1) svg.Polyline(line, false, fmt::format("pa-l{}", style));
      for (const auto& [x, y] : line) svg.Circle(x, y, 2.5, fmt::format("pa-p{}", style));
      i = j;
    }
    svg.EndGroup();
    if (c_map) {
      const double ly = top + 10 + 16 * static_cast<double>(k);
      svg.Line(left + pw + 10, ly, left + pw + 28, ly, fmt::format("pa-l{}", style));
      svg.Text(left + pw + 32, ly + 3, s.label, "pa-sm");
    }
  }
  return svg.Finish();
}

}  // namespace

std::string ProbeArtifactsJson(const ProbeArtifactsReport& report) {
  const auto& r = report.result;
  PaJson j;
  j["schema"] = "tpcal.identification/1";
  j["instrument"] = "probe_artifacts";
  j["source"] = report.source;
  j["artifacts_source"] = report.artifacts_source;
  j["machine"] = report.machine;
  j["artifacts"] = PaArtifactsJson(report.artifacts);
  j["fit"] = {{"touches", r.poses.num_touches},
              {"rank", r.poses.rank},
              {"dof", r.poses.dof},
              {"sigma_um", r.poses.sigma_um},
              {"probe_radius_mm", report.probe_radius_mm},
              {"weighted", r.poses.weighted},
              {"chi_scale", r.poses.weighted ? PaJson(r.poses.chi_scale) : PaJson(nullptr)}};
  const TablePose* ref = PaReferencePose(r.poses);
  j["reference"] = ref ? PaJson{{"a_deg", ref->a_deg}, {"c_deg", ref->c_deg}} : PaJson(nullptr);
  j["conventions"] = r.maps.conventions;
  j["a_deg"] = r.maps.a_deg;
  j["c_deg"] = r.maps.c_deg;
  j["poses"] = PaPosesJson(r.poses);
  j["faces"] = PaFacesJson(report);
  j["parameters"] = PaLinearErrorsJson(r.poses);
  j["maps"] = PaMapsJson(r.maps);
  j["not_identifiable"] = r.maps.not_identifiable;
  PaJson res = PaJson::array();
  for (std::size_t i = 0; i < r.poses.residuals_um.size(); ++i)
    res.push_back({{"line", i < report.lines.size() ? report.lines[i] : 0}, {"residual_um", r.poses.residuals_um[i]}});
  j["residuals"] = std::move(res);
  j["errors_yaml"] = report.errors_yaml;
  return j.dump(2) + "\n";
}

std::string ProbeArtifactsText(const ProbeArtifactsReport& report) {
  const auto& r = report.result;
  std::string o = PaHeaderLine(report);
  o += "conventions:\n";
  for (const std::string& c : r.maps.conventions) o += "  - " + c + "\n";
  o += "\ntable poses relative to the reference, value +- u (k=1), '-' not identifiable:\n";
  o += PaPoseTableText(r.poses);
  o += "\nlargest correlation between two components of each pose (its 6 x 6 covariance is in the JSON):\n";
  o += fmt::format("{:>7} {:>7}  rho (components)\n", "A deg", "C deg") + PaPoseCorrelationText(r.poses);
  for (const std::string& symbol : PaSymbols(r.maps)) o += "\n" + PaMapText(r.maps, symbol);
  const auto missing = PaNotIdentifiableLines(report);
  if (missing.empty()) {
    o += "\nnot identifiable: none\n";
  } else {
    o += fmt::format("\nnot identifiable ({}; no number is given for them):\n", missing.size());
    for (const std::string& s : missing) o += "  " + s + "\n";
  }
  return o;
}

std::string ProbeArtifactsHtml(const ProbeArtifactsReport& report) {
  const auto& r = report.result;
  const std::string title = "tpcal probe artifacts: " + report.source;
  std::string o = "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" + XmlEscape(title) +
                  "</title><style>body{font-family:sans-serif;margin:1.5em}table{border-collapse:collapse;"
                  "margin:0.5em 0}td,th{border:1px solid #ccc;padding:2px 6px;text-align:right;font-size:12px}"
                  "tr.paref{background:#eef}figure{margin:0.5em 0}</style></head>\n<body>\n";
  o += "<h1>" + XmlEscape(title) + "</h1>\n<pre>" + XmlEscape(PaHeaderLine(report)) + "</pre>\n";
  o += "<h2>Conventions</h2>\n<ul>\n";
  for (const std::string& c : r.maps.conventions) o += "<li>" + XmlEscape(c) + "</li>\n";
  o += "</ul>\n<h2>Table poses</h2>\n<p>Relative to the reference pose, value +- u (k=1); - not identifiable.</p>\n";
  o += PaPoseTableHtml(r.poses);
  o += "<h2>Error maps</h2>\n";
  for (const std::string& symbol : PaSymbols(r.maps)) {
    o += "<h3>" + XmlEscape(symbol) + "</h3>\n<figure>\n" + PaMapFigure(r.maps, symbol) + "</figure>\n";
    o += PaMapTableHtml(r.maps, symbol);
  }
  o += "<h2>Not identifiable</h2>\n";
  const auto missing = PaNotIdentifiableLines(report);
  if (missing.empty()) {
    o += "<p>none</p>\n";
  } else {
    o += "<ul>\n";
    for (const std::string& s : missing) o += "<li>" + XmlEscape(s) + "</li>\n";
    o += "</ul>\n";
  }
  return o + "</body></html>\n";
}

}  // namespace tpcal::pipeline
