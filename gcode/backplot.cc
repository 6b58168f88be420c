#include "gcode/backplot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "core/units.h"
#include "core/xml_escape.h"
#include "gcode/nc_format.h"
#include "kinematics/forward_kinematics.h"

namespace tpcal::gcode {
namespace {

using kinematics::AxisState;

const char* const kPalette[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"};

struct Seg {
  int op = 0;
  bool rapid = false;
  std::vector<Eigen::Vector3d> pts;  // part frame
  bool xy_arc = false;               // drawable as SVG arcs in the top view
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius = 0.0, angle = 0.0;
  bool clockwise = false;
};

// Top-view marks of what a tool-point path cannot show there: a reamed hole (circle of the tool
// radius about the hole axis) and a turned face (the circle the nose centre sweeps while the
// table spins, about the part Z axis = the C axis).
struct Mark {
  int op = 0;
  Eigen::Vector2d center_mm = Eigen::Vector2d::Zero();  // part XY
  double radius_mm = 0.0;
};

Eigen::Vector3d Tip(const IrProgram& prog, const AxisState& s) {
  return kinematics::NominalToolPointInPart(prog.machine, s, Eigen::Vector3d::Zero());
}

AxisState LerpAxes(const AxisState& a, const AxisState& b, double f) {
  AxisState s = a;
  s.x_mm += (b.x_mm - a.x_mm) * f;
  s.y_mm += (b.y_mm - a.y_mm) * f;
  s.z_mm += (b.z_mm - a.z_mm) * f;
  s.a_rad += (b.a_rad - a.a_rad) * f;
  s.b_rad += (b.b_rad - a.b_rad) * f;
  s.c_rad += (b.c_rad - a.c_rad) * f;
  return s;
}

std::string F2(double v) {
  char b[32];
  std::snprintf(b, sizeof(b), "%.2f", v);
  return b;
}

void Line(const IrProgram& prog, const AxisState& a, const AxisState& b, bool rapid, int op, double seg_deg,
          std::vector<Seg>* out) {
  Seg s;
  s.op = op;
  s.rapid = rapid;
  const double rot = RadToDeg(std::max({std::abs(b.a_rad - a.a_rad), std::abs(b.b_rad - a.b_rad), std::abs(b.c_rad - a.c_rad)}));
  const int n = std::max(1, static_cast<int>(std::ceil(rot / seg_deg)));
  for (int k = 0; k <= n; ++k) s.pts.push_back(Tip(prog, LerpAxes(a, b, static_cast<double>(k) / n)));
  if ((s.pts.front() - s.pts.back()).norm() < 1e-9 && n == 1) return;
  out->push_back(std::move(s));
}

std::vector<Seg> Segments(const IrProgram& prog, double seg_deg, std::vector<Mark>* marks) {
  std::vector<Seg> segs;
  double tool_radius_mm = 0.0;
  bool spinning = false;
  for (const Instr& in : prog.instrs) {
    if (in.kind == InstrKind::kToolChange && in.tool_index >= 0 &&
        in.tool_index < static_cast<int>(prog.tools.size())) {
      tool_radius_mm = prog.tools[in.tool_index].tool.radius_mm();
    }
    if (in.kind == InstrKind::kTableSpinStart) spinning = true;
    if (in.kind == InstrKind::kTableSpinStop) spinning = false;
    if (in.kind == InstrKind::kLinear && in.cutting && (spinning || in.feed_mode == FeedMode::kPerRevolution)) {
      const Eigen::Vector3d q = Tip(prog, in.end);
      marks->push_back({in.op, Eigen::Vector2d::Zero(), std::hypot(q.x(), q.y())});
    }
    if (in.kind == InstrKind::kDrillCycle && tool_radius_mm > 0) {
      AxisState bottom = in.start;
      bottom.x_mm = in.drill.x_mm;
      bottom.y_mm = in.drill.y_mm;
      bottom.z_mm = in.drill.bottom_z_mm;
      marks->push_back({in.op, Tip(prog, bottom).head<2>(), tool_radius_mm});
    }
    switch (in.kind) {
      case InstrKind::kRapid:
      case InstrKind::kIndex:
        if (in.axis_mask == 0x3F) Line(prog, in.start, in.end, true, in.op, seg_deg, &segs);
        break;
      case InstrKind::kLinear:
        Line(prog, in.start, in.end, false, in.op, seg_deg, &segs);
        break;
      case InstrKind::kArc: {
        Seg s;
        s.op = in.op;
        const Eigen::Vector2d r0(in.start.x_mm - in.arc_center_xy_mm.x(), in.start.y_mm - in.arc_center_xy_mm.y());
        const int n = std::max(2, static_cast<int>(std::ceil(RadToDeg(in.arc_angle_rad) / seg_deg)));
        for (int k = 0; k <= n; ++k) {
          const double a = (in.clockwise ? -1.0 : 1.0) * in.arc_angle_rad * k / n;
          AxisState p = in.start;
          p.x_mm = in.arc_center_xy_mm.x() + std::cos(a) * r0.x() - std::sin(a) * r0.y();
          p.y_mm = in.arc_center_xy_mm.y() + std::sin(a) * r0.x() + std::cos(a) * r0.y();
          s.pts.push_back(Tip(prog, p));
        }
        // Part Z along machine Z (A = B = 0): the arc stays an arc of the same sense in part XY.
        if (std::abs(in.start.a_rad) < 1e-12 && std::abs(in.start.b_rad) < 1e-12) {
          AxisState c = in.start;
          c.x_mm = in.arc_center_xy_mm.x();
          c.y_mm = in.arc_center_xy_mm.y();
          s.xy_arc = true;
          s.center = Tip(prog, c);
          s.radius = r0.norm();
          s.angle = in.arc_angle_rad;
          s.clockwise = in.clockwise;
        }
        segs.push_back(std::move(s));
        break;
      }
      case InstrKind::kDrillCycle: {
        const DrillCycle& d = in.drill;
        AxisState top = in.start, r = in.start, bottom = in.start;
        top.x_mm = r.x_mm = bottom.x_mm = d.x_mm;
        top.y_mm = r.y_mm = bottom.y_mm = d.y_mm;
        r.z_mm = d.r_z_mm;
        bottom.z_mm = d.bottom_z_mm;
        Line(prog, in.start, top, true, in.op, seg_deg, &segs);
        Line(prog, top, r, true, in.op, seg_deg, &segs);
        Line(prog, r, bottom, false, in.op, seg_deg, &segs);
        Line(prog, bottom, r, false, in.op, seg_deg, &segs);
        Line(prog, r, in.end, true, in.op, seg_deg, &segs);
        break;
      }
      default:
        break;
    }
  }
  return segs;
}

// One view: u = part X, v = part Y (top) or part Z (side).
struct View {
  std::string title;
  int v_axis = 1;
  double x0 = 0, y0 = 0, w = 0, h = 0;  // panel on the page (px)
  double umin = 0, umax = 1, vmin = 0, vmax = 1, scale = 1;
  double X(double u) const { return x0 + (u - umin) * scale; }
  double Y(double v) const { return y0 + (vmax - v) * scale; }
};

double NiceLength(double target) {
  const double p = std::pow(10.0, std::floor(std::log10(target)));
  for (double m : {5.0, 2.0, 1.0}) {
    if (m * p <= target) return m * p;
  }
  return p;
}

}  // namespace

std::string BackplotSvg(const IrProgram& prog, const BackplotOptions& o, const std::string& title, BackplotStats* stats) {
  std::vector<Mark> marks;
  const std::vector<Seg> segs = Segments(prog, o.arc_segment_deg, &marks);
  BackplotStats st;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const Seg& s : segs) {
    for (const auto& p : s.pts) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    for (std::size_t k = 1; k < s.pts.size(); ++k) {
      (s.rapid ? st.rapid_length_mm : st.feed_length_mm) += (s.pts[k] - s.pts[k - 1]).norm();
    }
  }
  for (const Mark& m : marks) {  // top view: part X and Y only
    lo.head<2>() = lo.head<2>().cwiseMin(m.center_mm - Eigen::Vector2d::Constant(m.radius_mm));
    hi.head<2>() = hi.head<2>().cwiseMax(m.center_mm + Eigen::Vector2d::Constant(m.radius_mm));
  }
  if (segs.empty()) lo = hi = Eigen::Vector3d::Zero();
  const double margin = 40.0, title_h = 40.0;
  const double panel_w = (o.width_px - 3 * margin) / 2.0;
  View views[2];
  views[0].title = "top view (part X right, Y up)";
  views[0].v_axis = 1;
  views[1].title = "side view (part X right, Z up)";
  views[1].v_axis = 2;
  double panel_h = 0;
  for (int i = 0; i < 2; ++i) {
    View& v = views[i];
    const double pad = 0.03 * std::max({hi.x() - lo.x(), hi[v.v_axis] - lo[v.v_axis], 1.0});
    v.umin = lo.x() - pad;
    v.umax = hi.x() + pad;
    v.vmin = lo[v.v_axis] - pad;
    v.vmax = hi[v.v_axis] + pad;
    v.scale = panel_w / (v.umax - v.umin);
    panel_h = std::max(panel_h, (v.vmax - v.vmin) * v.scale);
  }
  // Both panels share the page height; a view shorter than the panel is centred.
  panel_h = std::min(panel_h, 1.2 * panel_w);
  for (int i = 0; i < 2; ++i) {
    View& v = views[i];
    const double need = (v.vmax - v.vmin) * v.scale;
    if (need > panel_h) v.scale *= panel_h / need;
    v.w = panel_w;
    v.h = panel_h;
    v.x0 = margin + i * (panel_w + margin);
    v.y0 = title_h + 30 + 0.5 * (panel_h - (v.vmax - v.vmin) * v.scale);
  }
  const int n_ops = static_cast<int>(prog.operation_names.size());
  const double legend_y = title_h + 30 + panel_h + 50;
  const double height = legend_y + 22.0 * (n_ops + 2) + 10;

  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << F2(o.width_px) << "\" height=\"" << F2(height)
      << "\" viewBox=\"0 0 " << F2(o.width_px) << " " << F2(height) << "\" font-family=\"sans-serif\">\n";
  svg << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  svg << "<text x=\"" << F2(margin) << "\" y=\"28\" font-size=\"18\">" << XmlEscape(title) << "</text>\n";
  for (int i = 0; i < 2; ++i) {
    const View& v = views[i];
    svg << "<g id=\"view" << i << "\">\n";
    svg << "<text x=\"" << F2(v.x0) << "\" y=\"" << F2(title_h + 18) << "\" font-size=\"14\">" << XmlEscape(v.title)
        << "</text>\n";
    svg << "<rect x=\"" << F2(v.x0) << "\" y=\"" << F2(title_h + 30) << "\" width=\"" << F2(v.w) << "\" height=\""
        << F2(v.h) << "\" fill=\"none\" stroke=\"#cccccc\"/>\n";
    for (const Seg& s : segs) {
      const char* colour = kPalette[(std::max(s.op, 1) - 1) % 10];
      std::ostringstream d;
      if (i == 0 && s.xy_arc) {
        const int pieces = std::max(1, static_cast<int>(std::ceil(s.angle / DegToRad(120.0) - 1e-9)));
        const Eigen::Vector3d r0 = s.pts.front() - s.center;
        d << "M" << F2(v.X(s.pts.front().x())) << " " << F2(v.Y(s.pts.front().y()));
        for (int k = 1; k <= pieces; ++k) {
          const double a = (s.clockwise ? -1.0 : 1.0) * s.angle * k / pieces;
          const double x = s.center.x() + std::cos(a) * r0.x() - std::sin(a) * r0.y();
          const double y = s.center.y() + std::sin(a) * r0.x() + std::cos(a) * r0.y();
          const double r = s.radius * v.scale;
          // Screen Y points down, so the part frame's counter-clockwise (+angle) is the screen's
          // negative-angle direction: sweep flag 0; clockwise: 1.
          d << " A" << F2(r) << " " << F2(r) << " 0 0 " << (s.clockwise ? 1 : 0) << " " << F2(v.X(x)) << " " << F2(v.Y(y));
        }
        ++st.svg_arcs;
      } else {
        for (std::size_t k = 0; k < s.pts.size(); ++k) {
          d << (k == 0 ? "M" : " L") << F2(v.X(s.pts[k].x())) << " " << F2(v.Y(s.pts[k][v.v_axis]));
        }
      }
      svg << "<path d=\"" << d.str() << "\" fill=\"none\" stroke=\"" << colour << "\" stroke-width=\""
          << (s.rapid ? "0.8" : "1.2") << "\"" << (s.rapid ? " stroke-dasharray=\"4 3\"" : "") << "/>\n";
      if (i == 0) ++st.polylines;
    }
    if (i == 0) {
      for (const Mark& m : marks) {
        svg << "<circle cx=\"" << F2(v.X(m.center_mm.x())) << "\" cy=\"" << F2(v.Y(m.center_mm.y())) << "\" r=\""
            << F2(m.radius_mm * v.scale) << "\" fill=\"none\" stroke=\"" << kPalette[(std::max(m.op, 1) - 1) % 10]
            << "\" stroke-width=\"0.8\"/>\n";
        ++st.marks;
      }
    }
    // Scale bar: a round length near a fifth of the panel.
    const double len_mm = NiceLength((v.umax - v.umin) / 5.0);
    const double bx = v.x0 + 10, by = title_h + 30 + v.h - 12;
    svg << "<line x1=\"" << F2(bx) << "\" y1=\"" << F2(by) << "\" x2=\"" << F2(bx + len_mm * v.scale) << "\" y2=\""
        << F2(by) << "\" stroke=\"black\" stroke-width=\"2\"/>\n";
    svg << "<text x=\"" << F2(bx) << "\" y=\"" << F2(by - 5) << "\" font-size=\"12\">" << FormatNumber(len_mm, 3)
        << " mm</text>\n";
    svg << "</g>\n";
  }
  // Legend.
  svg << "<g id=\"legend\" font-size=\"13\">\n";
  for (int k = 0; k < n_ops; ++k) {
    const double y = legend_y + 22.0 * k;
    std::string tool;
    for (const Instr& in : prog.instrs) {
      if (in.kind == InstrKind::kOperationStart && in.op == k + 1 && in.tool_index >= 0) {
        const IrTool& t = prog.tools[in.tool_index];
        tool = "T" + std::to_string(t.number) + " " + t.tool.name;
      }
    }
    svg << "<line x1=\"" << F2(margin) << "\" y1=\"" << F2(y) << "\" x2=\"" << F2(margin + 30) << "\" y2=\"" << F2(y)
        << "\" stroke=\"" << kPalette[k % 10] << "\" stroke-width=\"3\"/>\n";
    svg << "<text x=\"" << F2(margin + 40) << "\" y=\"" << F2(y + 4) << "\">OP " << k + 1 << " "
        << XmlEscape(prog.operation_names[k]) << " (" << XmlEscape(tool) << ")</text>\n";
  }
  const double y = legend_y + 22.0 * n_ops;
  svg << "<line x1=\"" << F2(margin) << "\" y1=\"" << F2(y) << "\" x2=\"" << F2(margin + 30) << "\" y2=\"" << F2(y)
      << "\" stroke=\"black\" stroke-width=\"0.8\" stroke-dasharray=\"4 3\"/>\n";
  svg << "<text x=\"" << F2(margin + 40) << "\" y=\"" << F2(y + 4) << "\">rapid</text>\n";
  svg << "<line x1=\"" << F2(margin + 120) << "\" y1=\"" << F2(y) << "\" x2=\"" << F2(margin + 150) << "\" y2=\""
      << F2(y) << "\" stroke=\"black\" stroke-width=\"1.2\"/>\n";
  svg << "<text x=\"" << F2(margin + 160) << "\" y=\"" << F2(y + 4) << "\">feed</text>\n";
  svg << "</g>\n</svg>\n";
  if (stats) *stats = st;
  return svg.str();
}

}  // namespace tpcal::gcode
