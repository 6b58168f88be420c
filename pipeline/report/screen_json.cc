#include "pipeline/report/screen_json.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace tpcal::pipeline {

using json = nlohmann::ordered_json;

json OutliersJson(const std::vector<ScreenedPoint>& points) {
  json a = json::array();
  for (const auto& p : points)
    a.push_back({{"line", p.line}, {"feature", p.feature}, {"kind", p.kind}, {"deviation_um", p.deviation_um},
                 {"reason", p.reason}, {"left_out", p.left_out}});
  return a;
}

json LocalDefectsJson(const std::vector<LocalDefect>& defects) {
  json a = json::array();
  for (const auto& d : defects)
    a.push_back({{"feature", d.feature}, {"n_points", d.n_points}, {"peak_um", d.peak_um}, {"mean_um", d.mean_um},
                 {"centre_mm", {d.centre_mm.x(), d.centre_mm.y(), d.centre_mm.z()}}, {"extent_mm", d.extent_mm},
                 {"lines", d.lines}});
  return a;
}

std::string PatchText(const LocalDefect& d) {
  return fmt::format("{}: {} points, peak {:+.2f} um, mean {:+.2f} um, over {:.1f} mm at ({:.1f}, {:.1f}, {:.1f}) mm, lines {}",
                     d.feature, d.n_points, d.peak_um, d.mean_um, 2.0 * d.extent_mm, d.centre_mm.x(), d.centre_mm.y(),
                     d.centre_mm.z(), fmt::join(d.lines, " "));
}

std::string ScreenText(const std::vector<ScreenedPoint>& points, const std::vector<LocalDefect>& defects,
                       double sigma_um) {
  std::string o;
  for (const auto& d : defects) o += "  local defect on " + PatchText(d) + "\n";
  if (points.empty()) return o;
  const bool left_out = points.front().left_out;
  o += fmt::format("{} point(s) {} by the outlier screen (noise from neighbours {:.3f} um):\n", points.size(),
                   left_out ? "left out" : "flagged but kept (--keep-outliers)", sigma_um);
  for (std::size_t k = 0; k < points.size() && k < 10; ++k)
    o += (points[k].line > 0 ? fmt::format("  line {}: ", points[k].line)
                                 : fmt::format("  point {}: ", points[k].point_index + 1)) +
         points[k].reason + "\n";
  if (points.size() > 10) o += fmt::format("  ... and {} more (JSON: outliers)\n", points.size() - 10);
  return o;
}

}  // namespace tpcal::pipeline
