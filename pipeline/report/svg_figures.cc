#include "pipeline/report/svg_figures.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "pipeline/report/svg_writer.h"

namespace tpcal::pipeline {
namespace {

constexpr double kUmPerMm = 1000.0;

// One style sheet for every figure (also used standalone).
constexpr const char* kCss =
    ".ax{stroke:#888;stroke-width:1;fill:none}.grid{stroke:#ddd;stroke-width:1;fill:none}"
    ".ref{stroke:#888;stroke-width:1;stroke-dasharray:4 3;fill:none}"
    ".nom{stroke:#555;stroke-width:1;fill:#fff}.meas{stroke:#1f5fa8;stroke-width:1.2;fill:none}"
    ".err{stroke:#c0392b;stroke-width:1.6;fill:none}.vec{stroke:#1f5fa8;stroke-width:1.8;fill:none}"
    ".vec2{stroke:#7b3fa0;stroke-width:1.8;fill:none}.prof{stroke:#1f5fa8;stroke-width:1.3;fill:#1f5fa8;fill-opacity:0.08}"
    ".bar{stroke:#1f5fa8;stroke-width:2;fill:none}.pt{stroke:#1f5fa8;fill:#1f5fa8}"
    ".truth{stroke:#c0392b;fill:none;stroke-width:1.5}.lbl{fill:#222}.sm{fill:#555;font-size:9px}"
    ".rms{fill:#9bb8dd;stroke:none}.bad{fill:#e6a19a;stroke:#c0392b}"
    ".ttl{fill:#000;font-size:13px;font-weight:bold}.na{fill:#999;font-style:italic}.zero{stroke:#444;stroke-width:1}";


const gdt::CharacteristicSpec* FindHolePattern(const gdt::InspectionPlan& plan) {
  for (const auto& c : plan.characteristics)
    if (c.type == gdt::CharacteristicType::kHolePattern) return &c;
  return nullptr;
}

}  // namespace

std::string ShortIsoSymbol(const std::string& symbol) {
  std::string s = symbol.substr(0, symbol.find(" ("));
  s = s.substr(0, s.find(" for "));
  if (const auto eq = s.find(" = "); eq != std::string::npos) s = s.substr(eq + 3);
  return s;
}

std::optional<Figure> HolePositionsFigure(const gdt::InspectionPlan& plan, const gdt::InspectionResult& inspection,
                                          const FigureOptions& options) {
  const gdt::CharacteristicSpec* spec = FindHolePattern(plan);
  if (!spec || !spec->nominal_radius_mm) return std::nullopt;
  const gdt::FittedFeature* pitch = inspection.Feature(spec->feature);
  if (!pitch || pitch->member_centers_mm.empty() || pitch->members.size() != pitch->member_centers_mm.size())
    return std::nullopt;
  const std::size_t n = pitch->members.size();
  const double r_nom = *spec->nominal_radius_mm;
  std::vector<double> angles_deg = spec->nominal_angles_deg;
  if (angles_deg.size() != n) {
    angles_deg.clear();
    const double first = spec->first_angle_deg.value_or(0.0);
    const double step = spec->pitch_deg.value_or(360.0 / static_cast<double>(n));
    for (std::size_t k = 0; k < n; ++k) angles_deg.push_back(first + step * static_cast<double>(k));
  }

  const double W = 560, H = 600, cx = W / 2, cy = 310;
  const double s = 220.0 / (r_nom * 1.15);  // px per mm of the part
  const double mag = options.position_magnification;
  SvgWriter svg(W, H, "Hole positions", kCss);
  svg.Text(16, 24, fmt::format("Hole positions in the datum XY plane, errors x{:g}", mag), "ttl");
  svg.Line(cx - 260, cy, cx + 260, cy, "grid");
  svg.Line(cx, cy - 260, cx, cy + 260, "grid");
  svg.Text(cx + 262, cy - 4, "X", "sm", "end");
  svg.Text(cx + 4, cy - 250, "Y", "sm");
  svg.Circle(cx, cy, r_nom * s, "ref");
  double max_err_um = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double a = angles_deg[k] * std::numbers::pi / 180.0;
    const double nx = r_nom * std::cos(a), ny = r_nom * std::sin(a);
    const Eigen::Vector2d err_mm = pitch->member_centers_mm[k] - Eigen::Vector2d(nx, ny);
    max_err_um = std::max(max_err_um, err_mm.norm() * kUmPerMm);
    const double px = cx + nx * s, py = cy - ny * s;
    svg.BeginGroup("hole", fmt::format("{}: dx = {:.2f} um, dy = {:.2f} um", pitch->members[k],
                                       err_mm.x() * kUmPerMm, err_mm.y() * kUmPerMm));
    svg.Circle(px, py, 4, "nom");
    svg.Arrow(px, py, px + err_mm.x() * mag * s, py - err_mm.y() * mag * s, "err", 5);
    svg.Text(cx + (r_nom * 1.1) * std::cos(a) * s, cy - (r_nom * 1.1) * std::sin(a) * s + 4, pitch->members[k], "sm",
             "middle");
    svg.EndGroup();
  }
  // Scale bar: a nice length in um at the magnified scale.
  const double bar_um = NiceStep(std::max(max_err_um, 1.0), 2);
  const double bar_px = bar_um / kUmPerMm * mag * s;
  svg.Line(24, H - 30, 24 + bar_px, H - 30, "err");
  svg.Text(28 + bar_px, H - 26, fmt::format("{:g} um (x{:g})", bar_um, mag), "sm");
  svg.Text(W - 16, H - 26, fmt::format("dashed: nominal pitch circle R = {:g} mm; largest error {:.2f} um", r_nom,
                                       max_err_um),
           "sm", "end");
  return Figure{"hole_positions",
                fmt::format("Hole centres ({}) versus nominal positions, position errors magnified x{:g}.",
                            spec->feature, mag),
                svg.Finish()};
}

std::vector<gdt::ProfileSample> DrawnProfile(const std::vector<gdt::ProfileSample>& profile, std::size_t bins) {
  if (profile.size() <= 2 * bins) return profile;
  std::vector<gdt::ProfileSample> out;
  out.reserve(2 * bins);
  std::size_t i = 0;
  const double start_deg = profile.front().theta_deg;  // sorted by theta, over one turn
  for (std::size_t b = 0; b < bins && i < profile.size(); ++b) {
    const double end_deg = start_deg + 360.0 * static_cast<double>(b + 1) / static_cast<double>(bins);
    std::size_t lo = i, hi = i;
    for (; i < profile.size() && (profile[i].theta_deg < end_deg || b + 1 == bins); ++i) {
      if (profile[i].dr_um < profile[lo].dr_um) lo = i;
      if (profile[i].dr_um > profile[hi].dr_um) hi = i;
    }
    if (i == lo) continue;  // empty bin
    out.push_back(profile[std::min(lo, hi)]);
    if (hi != lo) out.push_back(profile[std::max(lo, hi)]);
  }
  return out;
}

std::optional<Figure> CircularityFigure(const gdt::InspectionResult& inspection, const FigureOptions& options) {
  std::vector<const gdt::CharacteristicResult*> profiles;
  for (const auto& c : inspection.characteristics)
    if (c.type == gdt::CharacteristicType::kCircularity && c.profile.size() >= 3) profiles.push_back(&c);
  if (profiles.empty()) return std::nullopt;
  const double mag = options.profile_magnification;
  const int cols = std::min<int>(3, static_cast<int>(profiles.size()));
  const int rows = (static_cast<int>(profiles.size()) + cols - 1) / cols;
  const double pw = 250, ph = 270, r0 = 80;
  const double W = pw * cols, H = ph * rows + 56;
  SvgWriter svg(W, H, "Circularity profiles", kCss);
  svg.Text(16, 24, fmt::format("Circularity profiles (deviation from the LS circle), magnified x{:g}", mag), "ttl");
  for (std::size_t i = 0; i < profiles.size(); ++i) {
    const auto& c = *profiles[i];
    const double ox = pw * static_cast<double>(i % static_cast<std::size_t>(cols)) + pw / 2;
    const double oy = 40 + ph * static_cast<double>(i / static_cast<std::size_t>(cols)) + ph / 2;
    const gdt::FittedFeature* f = c.features.empty() ? nullptr : inspection.Feature(c.features.front());
    double radius_mm = 100.0;
    if (f) {
      if (auto r = gdt::RadiusOf(*f); r.ok()) radius_mm = *r;
    }
    const double s = r0 / radius_mm;                       // px per mm of the part
    const double px_per_um = mag * s / kUmPerMm;           // magnified deviation scale
    double max_abs = 0;
    for (const auto& p : c.profile) max_abs = std::max(max_abs, std::abs(p.dr_um));
    const double ring_um = NiceStep(std::max(max_abs, 0.1), 2);
    svg.BeginGroup("profile", c.name);
    svg.Circle(ox, oy, r0, "ref");
    for (double sign : {-1.0, 1.0}) {
      const double rr = r0 + sign * ring_um * px_per_um;
      if (rr > 2 && rr < 120) svg.Circle(ox, oy, rr, "grid");
    }
    svg.Line(ox - 118, oy, ox + 118, oy, "grid");
    svg.Line(ox, oy - 118, ox, oy + 118, "grid");
    std::vector<std::pair<double, double>> pts;
    bool clipped = false;
    constexpr std::size_t kDrawnBins = 1440;  // 0.25 deg: finer than the ~600 px of a panel's circle
    for (const auto& p : DrawnProfile(c.profile, kDrawnBins)) {
      double rr = r0 + p.dr_um * px_per_um;
      if (rr < 2 || rr > 120) { clipped = true; rr = std::clamp(rr, 2.0, 120.0); }
      const double a = p.theta_deg * std::numbers::pi / 180.0;
      pts.emplace_back(ox + rr * std::cos(a), oy - rr * std::sin(a));
    }
    svg.Polyline(pts, true, "prof");
    const auto value = c.Value("circularity_um");
    svg.Text(ox, oy - ph / 2 + 14, fmt::format("{} ({})", c.features.empty() ? c.name : c.features.front(), c.name),
             "lbl", "middle");
    svg.Text(ox, oy + ph / 2 - 14,
             fmt::format("circularity {} um, rings +-{:g} um{}", value ? fmt::format("{:.2f}", *value) : "-", ring_um,
                         clipped ? ", clipped" : ""),
             "sm", "middle");
    svg.EndGroup();
  }
  svg.Text(16, H - 8, fmt::format("dashed: LS circle; theta from datum +X about +Z; deviation x{:g}", mag), "sm");
  return Figure{"circularity",
                fmt::format("Circularity profiles dr(theta) from the LS circle, magnified x{:g}.", mag), svg.Finish()};
}

namespace {
struct Vec2Item {
  std::string label;
  double a = 0, b = 0;
};

void VectorPanel(SvgWriter& svg, double ox, double oy, const std::string& title, const std::string& ax,
                 const std::string& bx, const std::string& unit, const std::vector<Vec2Item>& items,
                 const char* cls) {
  svg.Text(ox, oy - 150, title, "lbl", "middle");
  double max_abs = 0;
  for (const auto& v : items) max_abs = std::max(max_abs, std::hypot(v.a, v.b));
  const double step = NiceStep(std::max(max_abs, 0.1), 2);
  const double full = std::ceil(std::max(max_abs, 0.1) / step) * step;
  const double s = 120.0 / full;  // px per unit
  for (double r = step; r <= full + 1e-9; r += step) svg.Circle(ox, oy, r * s, "grid");
  svg.Line(ox - 130, oy, ox + 130, oy, "ax");
  svg.Line(ox, oy - 130, ox, oy + 130, "ax");
  svg.Text(ox + 132, oy + 4, ax, "sm");
  svg.Text(ox + 4, oy - 132, bx, "sm");
  svg.Text(ox, oy + 146, fmt::format("rings every {:g} {}", step, unit), "sm", "middle");
  double ly = oy - 120;
  for (std::size_t k = 0; k < items.size(); ++k) {
    const auto& v = items[k];
    svg.BeginGroup("vector", fmt::format("{}: ({:.2f}, {:.2f}) {}", v.label, v.a, v.b, unit));
    const double ex = ox + v.a * s, ey = oy - v.b * s;
    svg.Arrow(ox, oy, ex, ey, cls, 7);
    svg.Text(ex + 4, ey - 4, std::to_string(k + 1), "sm");
    svg.EndGroup();
    svg.Text(ox + 150, ly, fmt::format("{} {}: ({:.2f}, {:.2f})", k + 1, v.label, v.a, v.b), "sm");
    ly += 13;
  }
}
}  // namespace

std::optional<Figure> VectorsFigure(const gdt::InspectionResult& inspection) {
  std::vector<Vec2Item> conc, par;
  for (const auto& c : inspection.characteristics) {
    const std::string label = c.features.size() >= 2 ? c.features[0] + "/" + c.features[1] : c.name;
    if (c.type == gdt::CharacteristicType::kConcentricity) {
      const auto dx = c.Value("dx_um"), dy = c.Value("dy_um");
      if (dx && dy) conc.push_back({label, *dx, *dy});
    } else if (c.type == gdt::CharacteristicType::kParallelism) {
      const auto da = c.Value("da_urad"), db = c.Value("db_urad");
      if (da && db) par.push_back({label, *da, *db});
    }
  }
  if (conc.empty() && par.empty()) return std::nullopt;
  const double panel = 500;
  const int panels = (conc.empty() ? 0 : 1) + (par.empty() ? 0 : 1);
  SvgWriter svg(panel * panels, 380, "Concentricity and parallelism vectors", kCss);
  svg.Text(16, 24, "Concentricity and parallelism vectors (datum frame)", "ttl");
  double ox = 160;
  if (!conc.empty()) {
    VectorPanel(svg, ox, 200, "concentricity (dx, dy), um", "dx", "dy", "um", conc, "vec");
    ox += panel;
  }
  if (!par.empty()) VectorPanel(svg, ox, 200, "parallelism (da, db), urad", "da", "db", "urad", par, "vec2");
  return Figure{"vectors",
                "Concentricity (dx, dy) of each feature to its datum in um, and parallelism (da about X, db about Y) "
                "in urad.",
                svg.Finish()};
}

std::optional<Figure> MachineErrorsFigure(std::span<const kinematics::ParameterEstimate> parameters,
                                          const std::map<std::string, double>& truth) {
  if (parameters.empty()) return std::nullopt;
  // Units in order of first appearance.
  std::vector<std::string> units;
  for (const auto& p : parameters)
    if (std::find(units.begin(), units.end(), p.unit) == units.end()) units.push_back(p.unit);

  const double W = 760, label_w = 290, plot_x0 = label_w + 20, plot_w = W - plot_x0 - 30, row_h = 22;
  const double H = 50 + static_cast<double>(units.size()) * 50 + static_cast<double>(parameters.size()) * row_h + 30;
  SvgWriter svg(W, H, "Identified machine errors", kCss);
  svg.Text(16, 24, "Identified machine errors with 95 % intervals (ISO 230-1 symbols)", "ttl");
  double y = 50;
  for (const auto& unit : units) {
    double extent = 0;
    for (const auto& p : parameters) {
      if (p.unit != unit) continue;
      if (p.identifiable)
        extent = std::max({extent, std::abs(p.ci95_low), std::abs(p.ci95_high), std::abs(p.value)});
      if (auto it = truth.find(p.name); it != truth.end()) extent = std::max(extent, std::abs(it->second));
    }
    const double step = NiceStep(std::max(extent, 0.1) * 2.0, 6);
    const double half = std::ceil(std::max(extent, 0.1) * 1.05 / step) * step;
    auto X = [&](double v) { return plot_x0 + (v + half) / (2 * half) * plot_w; };
    // Axis with ticks.
    y += 18;
    svg.Text(16, y, fmt::format("unit: {}", unit), "lbl");
    svg.Line(plot_x0, y, plot_x0 + plot_w, y, "ax");
    for (double t = -half; t <= half + 1e-9; t += step) {
      svg.Line(X(t), y - 3, X(t), y + 3, "ax");
      svg.Text(X(t), y - 6, fmt::format("{:g}", std::abs(t) < 1e-12 ? 0.0 : t), "sm", "middle");
    }
    const double y_top = y;
    y += 14;
    for (const auto& p : parameters) {
      if (p.unit != unit) continue;
      const double yc = y + row_h / 2;
      const std::string iso = ShortIsoSymbol(p.iso_symbol);
      const std::string label = iso.empty() || iso == p.name ? p.name : p.name + "  [" + iso + "]";
      svg.Text(label_w + 10, yc + 4, label, "lbl", "end");
      if (p.identifiable) {
        svg.BeginGroup("param", fmt::format("{} = {:.3f} {} (u = {:.3f}, 95 %: [{:.3f}, {:.3f}])", p.name, p.value,
                                            p.unit, p.u, p.ci95_low, p.ci95_high));
        svg.Line(X(p.ci95_low), yc, X(p.ci95_high), yc, "bar");
        svg.Line(X(p.ci95_low), yc - 5, X(p.ci95_low), yc + 5, "bar");
        svg.Line(X(p.ci95_high), yc - 5, X(p.ci95_high), yc + 5, "bar");
        svg.Circle(X(p.value), yc, 3.5, "pt");
        svg.EndGroup();
      } else {
        svg.Text(X(0) + 8, yc + 4, "not identifiable on this piece (see the identifiability table)", "na");
      }
      if (auto it = truth.find(p.name); it != truth.end()) svg.Diamond(X(it->second), yc, 5, "truth");
      y += row_h;
    }
    svg.Line(X(0), y_top, X(0), y, "zero");
    y += 16;
  }
  svg.Text(16, H - 10,
           truth.empty() ? "dot: estimate; bar: 95 % interval"
                         : "dot: estimate; bar: 95 % interval; red diamond: stated truth of the sample",
           "sm");
  return Figure{"machine_errors",
                "Identified machine error parameters with their 95 % intervals; non-identifiable parameters get no "
                "value.",
                svg.Finish()};
}

std::optional<Figure> GapFigure(const DiagnosisResult& d) {
  if (d.by_feature.empty()) return std::nullopt;
  const double row_h = 16, label_w = 90, plot_w = 520, W = label_w + plot_w + 150;
  const double H = 70 + row_h * static_cast<double>(d.by_feature.size()) + 40;
  double extent = d.noise_sigma_um;
  for (const auto& g : d.by_feature) extent = std::max({extent, g.rms_um, std::abs(g.mean_um)});
  const double step = NiceStep(std::max(extent, 0.01) * 2.0, 6);
  const double half = std::ceil(std::max(extent, 0.01) * 1.05 / step) * step;
  auto X = [&](double v) { return label_w + (v + half) / (2 * half) * plot_w; };
  SvgWriter svg(W, H, "Sim-to-real gap by feature", kCss);
  svg.Text(16, 24, "Gap of the identified model by feature (residual, um)", "ttl");
  const double y0 = 56;
  svg.Line(X(-half), y0, X(half), y0, "ax");
  for (double t = -half; t <= half + 1e-9; t += step) {
    svg.Line(X(t), y0 - 3, X(t), y0 + 3, "ax");
    svg.Text(X(t), y0 - 6, fmt::format("{:g}", std::abs(t) < 1e-12 ? 0.0 : t), "sm", "middle");
  }
  double y = y0 + 8;
  for (const auto& g : d.by_feature) {
    const double yc = y + row_h / 2;
    svg.BeginGroup("gap", fmt::format("{}: rms {:.3f} um, mean {:.3f} um, max {:.3f} um, z {:.1f}, {} points", g.group,
                                      g.rms_um, g.mean_um, g.max_abs_um, g.z, g.n_points));
    svg.Text(label_w - 8, yc + 4, g.group, "lbl", "end");
    svg.Rect(X(0), yc - 5, X(g.rms_um) - X(0), 10, g.stands_out ? "bad" : "rms");
    svg.Circle(X(g.mean_um), yc, 3, "pt");
    svg.Text(X(half) + 8, yc + 4, g.stands_out ? fmt::format("z {:.1f} stands out", g.z) : fmt::format("z {:.1f}", g.z),
             g.stands_out ? "lbl" : "sm");
    svg.EndGroup();
    y += row_h;
  }
  svg.Line(X(0), y0, X(0), y, "zero");
  if (d.noise_sigma_um > 0) {
    svg.Line(X(d.noise_sigma_um), y0, X(d.noise_sigma_um), y, "ref");
    svg.Text(X(d.noise_sigma_um) + 3, y + 12, fmt::format("noise sigma {:.2f} um", d.noise_sigma_um), "sm");
  }
  svg.Text(16, H - 8, "bar: RMS of the residual; dot: mean (signed); red: beyond noise", "sm");
  return Figure{"gap",
                fmt::format("Where the identified model misses: residual by feature (gap RMS {:.3f} um over {} points). "
                            "Verdict: {} ({}).",
                            d.rms_um, d.n_points, d.verdict.family, d.verdict.name),
                svg.Finish()};
}

std::vector<Figure> MakeFigures(const gdt::InspectionPlan& plan, const gdt::InspectionResult& inspection,
                                const kinematics::IdentificationResult* identification,
                                const std::map<std::string, double>& truth, const FigureOptions& options) {
  std::vector<Figure> out;
  if (identification) {
    if (auto f = MachineErrorsFigure(identification->parameters, truth)) out.push_back(std::move(*f));
  }
  if (auto f = HolePositionsFigure(plan, inspection, options)) out.push_back(std::move(*f));
  if (auto f = CircularityFigure(inspection, options)) out.push_back(std::move(*f));
  if (auto f = VectorsFigure(inspection)) out.push_back(std::move(*f));
  return out;
}

}  // namespace tpcal::pipeline
