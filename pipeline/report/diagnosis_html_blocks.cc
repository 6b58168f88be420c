#include "pipeline/report/diagnosis_html_blocks.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/xml_escape.h"

namespace tpcal::pipeline {
namespace {

std::string Joined(const std::vector<std::string>& items, const char* separator) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "" : separator) + XmlEscape(s);
  return out;
}

std::string Lines(const std::vector<std::size_t>& lines) {
  std::string out;
  for (std::size_t l : lines)
    if (l > 0) out += (out.empty() ? "" : " ") + std::to_string(l);
  return out.empty() ? "-" : out;
}

constexpr std::size_t kMaxListedPoints = 50;

// A table row of a patch: `kind`, feature, points, peak and mean, centre and extent, file lines.
std::string PatchRow(const std::string& kind, const LocalDefect& p) {
  return fmt::format(
      "<tr><td class=\"t\">{}</td><td class=\"t\">{}</td><td>{}</td><td>peak {:.2f}, mean {:.2f}</td>"
      "<td class=\"t\">centre ({:.1f}, {:.1f}, {:.1f}) mm, extent {:.1f} mm</td><td class=\"t\">{}</td></tr>\n",
      kind, XmlEscape(p.feature), p.n_points, p.peak_um, p.mean_um, p.centre_mm.x(), p.centre_mm.y(), p.centre_mm.z(),
      p.extent_mm, Lines(p.lines));
}

}  // namespace

std::string VerdictFamiliesHtml(const Verdict& v) {
  std::string h;
  if (v.families.size() > 1) h += "<p id=\"verdict-families\">Named together: " + Joined(v.families, " + ") + ".</p>\n";
  if (v.also && !v.also_indistinguishable_from.empty())
    h += "<p id=\"verdict-also-alike\">The second effect, " + XmlEscape(*v.also) +
         ", cannot be told apart on this piece and plan from: " + Joined(v.also_indistinguishable_from, ", ") + ".</p>\n";
  if (!v.partial.empty())
    h += "<p id=\"verdict-partial\">No candidate explains the gap; these explain part of it: " +
         Joined(v.partial, "; ") + ".</p>\n";
  return h;
}

std::string BaseShiftHtml(const DiagnosisResult& d) {
  if (!IsCatalogueFamily(d.verdict.family) || d.candidates.empty() || d.candidates.front().base_shift.empty())
    return "";
  const CandidateResult& best = d.candidates.front();
  std::string h = "<p>The identified machine errors without and with " + XmlEscape(best.name) +
                  " modelled (value &plusmn; u, k = 1):</p>\n"
                  "<table id=\"base-shift-table\"><tr><th class=\"t\">parameter</th><th>without</th><th>u without</th>"
                  "<th>with</th><th>u with</th><th>change / u with</th><th class=\"t\">unit</th></tr>\n";
  for (const auto& s : best.base_shift) {
    const double z = s.u_with > 0.0 ? (s.with_um - s.without_um) / s.u_with : 0.0;
    h += fmt::format(
        "<tr><td class=\"t\">{}</td><td>{:.3f}</td><td>{:.3f}</td><td>{:.3f}</td><td>{:.3f}</td><td>{:.1f}</td>"
        "<td class=\"t\">{}</td></tr>\n",
        XmlEscape(s.name), s.without_um, s.u_without, s.with_um, s.u_with, z, XmlEscape(s.unit));
  }
  return h + "</table>\n";
}

std::string ScreenHtml(const DiagnosisResult& d) {
  if (d.outliers.empty() && d.local_defects.empty() && d.explained_patches.empty()) return "";
  const bool left_out = std::all_of(d.outliers.begin(), d.outliers.end(), [](const auto& p) { return p.left_out; });
  std::string h = fmt::format(
      "<p id=\"screen\">Outlier screen (neighbour noise sigma {:.3f} um): {} local defect(s), {} flagged point(s), "
      "{}{}.</p>\n",
      d.neighbour_sigma_um, d.local_defects.size(), d.outliers.size(),
      left_out ? "left out of identification and diagnosis" : "kept in (--keep-outliers)",
      d.explained_patches.empty()
          ? ""
          : fmt::format("; {} patch(es) explained by the verdict's effect, kept", d.explained_patches.size()));
  h += "<table id=\"screen-table\"><tr><th class=\"t\">kind</th><th class=\"t\">feature</th><th>points</th>"
       "<th>size, um</th><th class=\"t\">where / reason</th><th class=\"t\">file lines</th></tr>\n";
  for (const auto& p : d.local_defects) h += PatchRow("local defect", p);
  for (const auto& p : d.explained_patches) h += PatchRow("patch explained by the verdict (kept)", p);
  for (std::size_t i = 0; i < d.outliers.size() && i < kMaxListedPoints; ++i) {
    const ScreenedPoint& p = d.outliers[i];
    h += fmt::format("<tr><td class=\"t\">{}</td><td class=\"t\">{}</td><td>1</td><td>{:.2f}</td>"
                     "<td class=\"t\">{}</td><td class=\"t\">{}</td></tr>\n",
                     XmlEscape(p.kind), XmlEscape(p.feature), p.deviation_um, XmlEscape(p.reason),
                     p.line > 0 ? std::to_string(p.line) : std::string("-"));
  }
  if (d.outliers.size() > kMaxListedPoints)
    h += fmt::format("<tr><td class=\"t\" colspan=\"6\">... {} more in the JSON</td></tr>\n",
                     d.outliers.size() - kMaxListedPoints);
  return h + "</table>\n";
}

}  // namespace tpcal::pipeline
