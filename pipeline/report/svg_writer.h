// A small SVG 1.1 writer for the report figures: plain elements (no script, no external
// resources), coordinates in SVG user units (px, y down), numbers printed with two decimals so
// the same figure gives the same bytes. Text is XML-escaped. Styling by CSS classes defined in
// the figure's own <style> element (svg_figures.cc), so a figure also renders standalone.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace tpcal::pipeline {


// "Nice" tick step (1, 2 or 5 x 10^k) so that about `target_ticks` steps cover `span` (> 0).
double NiceStep(double span, int target_ticks = 5);

class SvgWriter {
 public:
  // Opens <svg> of `width` x `height` px with a viewBox; `title` becomes its <title>.
  SvgWriter(double width, double height, std::string_view title, std::string_view css = {});

  void Line(double x1, double y1, double x2, double y2, std::string_view cls);
  // Arrow from (x1, y1) to (x2, y2) with a head of `head_px` (drawn as a path).
  void Arrow(double x1, double y1, double x2, double y2, std::string_view cls, double head_px = 6.0);
  void Circle(double cx, double cy, double r, std::string_view cls);
  void Rect(double x, double y, double w, double h, std::string_view cls);
  // Closed (or open) polyline through `points`.
  void Polyline(const std::vector<std::pair<double, double>>& points, bool closed, std::string_view cls);
  // anchor: "start", "middle" or "end".
  void Text(double x, double y, std::string_view text, std::string_view cls, std::string_view anchor = "start");
  // Diamond marker (truth values).
  void Diamond(double cx, double cy, double r, std::string_view cls);
  void BeginGroup(std::string_view cls, std::string_view tooltip = {});
  void EndGroup();

  // Closes the document and returns it. The writer is empty afterwards.
  std::string Finish();

 private:
  std::string out_;
  int open_groups_ = 0;
};

}  // namespace tpcal::pipeline
