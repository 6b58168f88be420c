#include "pipeline/report/svg_writer.h"
#include "core/xml_escape.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace tpcal::pipeline {

double NiceStep(double span, int target_ticks) {
  if (!(span > 0) || !std::isfinite(span)) return 1.0;
  const double raw = span / std::max(1, target_ticks);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / mag;
  const double nice = f <= 1.0 ? 1.0 : f <= 2.0 ? 2.0 : f <= 5.0 ? 5.0 : 10.0;
  return nice * mag;
}

namespace {
// Two decimals; -0.00 printed as 0.00 so equal figures give equal bytes.
std::string N(double v) {
  if (!std::isfinite(v)) v = 0.0;
  std::string s = fmt::format("{:.2f}", v);
  if (s == "-0.00") s = "0.00";
  return s;
}
}  // namespace

SvgWriter::SvgWriter(double width, double height, std::string_view title, std::string_view css) {
  out_ = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\" "
      "font-family=\"sans-serif\" font-size=\"11\">\n<title>{2}</title>\n",
      N(width), N(height), XmlEscape(title));
  if (!css.empty()) out_ += fmt::format("<style>{}</style>\n", css);
  out_ += fmt::format("<rect x=\"0\" y=\"0\" width=\"{}\" height=\"{}\" fill=\"white\"/>\n", N(width), N(height));
}

void SvgWriter::Line(double x1, double y1, double x2, double y2, std::string_view cls) {
  out_ += fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" class=\"{}\"/>\n", N(x1), N(y1), N(x2), N(y2),
                      cls);
}

void SvgWriter::Arrow(double x1, double y1, double x2, double y2, std::string_view cls, double head_px) {
  const double dx = x2 - x1, dy = y2 - y1;
  const double len = std::hypot(dx, dy);
  std::string d = fmt::format("M{},{} L{},{}", N(x1), N(y1), N(x2), N(y2));
  if (len > 1e-9) {
    const double ux = dx / len, uy = dy / len;
    const double h = std::min(head_px, 0.6 * len + 1.0);
    const double bx = x2 - h * ux, by = y2 - h * uy;
    d += fmt::format(" M{},{} L{},{} L{},{}", N(bx - 0.5 * h * uy), N(by + 0.5 * h * ux), N(x2), N(y2),
                     N(bx + 0.5 * h * uy), N(by - 0.5 * h * ux));
  }
  out_ += fmt::format("<path d=\"{}\" class=\"{}\"/>\n", d, cls);
}

void SvgWriter::Circle(double cx, double cy, double r, std::string_view cls) {
  out_ += fmt::format("<circle cx=\"{}\" cy=\"{}\" r=\"{}\" class=\"{}\"/>\n", N(cx), N(cy), N(r), cls);
}

void SvgWriter::Rect(double x, double y, double w, double h, std::string_view cls) {
  out_ += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" class=\"{}\"/>\n", N(x), N(y), N(w), N(h),
                      cls);
}

void SvgWriter::Polyline(const std::vector<std::pair<double, double>>& points, bool closed, std::string_view cls) {
  std::string pts;
  for (const auto& [x, y] : points) {
    if (!pts.empty()) pts += ' ';
    pts += N(x) + "," + N(y);
  }
  out_ += fmt::format("<{} points=\"{}\" class=\"{}\"/>\n", closed ? "polygon" : "polyline", pts, cls);
}

void SvgWriter::Text(double x, double y, std::string_view text, std::string_view cls, std::string_view anchor) {
  out_ += fmt::format("<text x=\"{}\" y=\"{}\" class=\"{}\" text-anchor=\"{}\">{}</text>\n", N(x), N(y), cls, anchor,
                      XmlEscape(text));
}

void SvgWriter::Diamond(double cx, double cy, double r, std::string_view cls) {
  Polyline({{cx, cy - r}, {cx + r, cy}, {cx, cy + r}, {cx - r, cy}}, true, cls);
}

void SvgWriter::BeginGroup(std::string_view cls, std::string_view tooltip) {
  out_ += fmt::format("<g class=\"{}\">", cls);
  if (!tooltip.empty()) out_ += fmt::format("<title>{}</title>", XmlEscape(tooltip));
  out_ += "\n";
  ++open_groups_;
}

void SvgWriter::EndGroup() {
  if (open_groups_ == 0) return;
  out_ += "</g>\n";
  --open_groups_;
}

std::string SvgWriter::Finish() {
  while (open_groups_ > 0) EndGroup();
  out_ += "</svg>\n";
  return std::exchange(out_, std::string());
}

}  // namespace tpcal::pipeline
