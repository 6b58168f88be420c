#include "gcode/safety.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/units.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/machine_model.h"

namespace tpcal::gcode {
namespace {

using kinematics::AxisState;

std::string Mm(double v) {
  std::ostringstream os;
  os.setf(std::ios::fixed);
  os.precision(3);
  os << v;
  return os.str();
}

Status Violation(const PostedText& posted, int index, const std::string& what) {
  std::string label = LabelOf(posted, index);
  if (label.empty()) label = "program start";
  return {StatusCode::kInvalidArgument, label + ": " + what};
}

AxisState Lerp(const AxisState& a, const AxisState& b, double f) {
  AxisState s = a;
  s.x_mm += (b.x_mm - a.x_mm) * f;
  s.y_mm += (b.y_mm - a.y_mm) * f;
  s.z_mm += (b.z_mm - a.z_mm) * f;
  s.a_rad += (b.a_rad - a.a_rad) * f;
  s.b_rad += (b.b_rad - a.b_rad) * f;
  s.c_rad += (b.c_rad - a.c_rad) * f;
  return s;
}

// Points of the tool in the tool frame (mm) used against the envelope: the cutting cylinder of a
// milling tool (end disc and rings up its flutes), the nose sphere of a turning insert.
struct ToolShape {
  std::vector<Eigen::Vector3d> points;
};
ToolShape ShapeOf(const testpieces::Tool& t) {
  ToolShape s;
  if (t.kind == testpieces::ToolKind::kTurningInsert) {
    const double r = t.corner_radius_mm;
    s.points.push_back(Eigen::Vector3d::Zero());
    for (int i = 0; i < 3; ++i) {
      for (double sign : {-1.0, 1.0}) s.points.push_back(sign * r * Eigen::Vector3d::Unit(i));
    }
    for (double x : {-1.0, 1.0}) {
      for (double y : {-1.0, 1.0}) {
        for (double z : {-1.0, 1.0}) s.points.push_back(r / std::sqrt(3.0) * Eigen::Vector3d(x, y, z));
      }
    }
    return s;
  }
  const double r = t.radius_mm();
  const double len = std::max(t.flute_length_mm, 1.0);
  const int levels = std::max(2, static_cast<int>(std::ceil(len / std::max(r, 1.0))) + 1);
  for (int l = 0; l < levels; ++l) {
    const double h = len * l / (levels - 1);
    s.points.emplace_back(0, 0, h);
    for (int k = 0; k < 24; ++k) {
      const double th = 2 * kPi * k / 24;
      s.points.emplace_back(r * std::cos(th), r * std::sin(th), h);
    }
  }
  return s;
}

// Volume removed by one feed move (part frame), for the in-process stock: a point inside the
// raw envelope but inside an earlier sweep is no longer material.
struct Sweep {
  enum class Kind { kTurn, kLine, kArc } kind = Kind::kLine;
  // kTurn: the nose centre's (radius from the C axis, height) segment, nose radius r.
  Eigen::Vector2d a = Eigen::Vector2d::Zero(), b = Eigen::Vector2d::Zero();
  // kLine: the tool tip from tip0 by d with the tool axis `axis`; kArc: tip on the circle of
  // radius rho0 about `center` (plane normal to `axis`) from direction u through `angle` (signed
  // about `axis`). Tool: cylinder of radius r over [0, length] up its axis.
  Eigen::Vector3d tip0 = Eigen::Vector3d::Zero(), d = Eigen::Vector3d::Zero(), axis = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d center = Eigen::Vector3d::Zero(), u = Eigen::Vector3d::UnitX();
  double rho0 = 0.0, angle = 0.0;
  double r = 0.0, length = 0.0;

  bool Contains(const Eigen::Vector3d& p, double tol) const {
    switch (kind) {
      case Kind::kTurn: {
        const Eigen::Vector2d q(std::hypot(p.x(), p.y()), p.z());
        const Eigen::Vector2d e = b - a;
        const double t = e.squaredNorm() > 0 ? std::clamp((q - a).dot(e) / e.squaredNorm(), 0.0, 1.0) : 0.0;
        return (q - (a + t * e)).norm() <= r + tol;
      }
      case Kind::kLine: {
        // Exists t in [0, 1]: 0 <= h(t) <= length and |w(t)| <= r (h along the axis, w across).
        const Eigen::Vector3d q0 = p - tip0;
        const double h0 = q0.dot(axis), dh = d.dot(axis);
        double lo = 0.0, hi = 1.0;
        if (std::abs(dh) < 1e-12) {
          if (h0 < -tol || h0 > length + tol) return false;
        } else {
          double t1 = (h0 - (length + tol)) / dh, t2 = (h0 + tol) / dh;
          if (t1 > t2) std::swap(t1, t2);
          lo = std::max(lo, t1);
          hi = std::min(hi, t2);
        }
        const Eigen::Vector3d w0 = q0 - h0 * axis, e = d - dh * axis;
        const double A = e.squaredNorm(), B = -2.0 * w0.dot(e), C = w0.squaredNorm() - (r + tol) * (r + tol);
        if (A < 1e-18) {
          if (C > 0) return false;
        } else {
          const double disc = B * B - 4 * A * C;
          if (disc < 0) return false;
          const double sq = std::sqrt(disc);
          lo = std::max(lo, (-B - sq) / (2 * A));
          hi = std::min(hi, (-B + sq) / (2 * A));
        }
        return lo <= hi;
      }
      case Kind::kArc: {
        const Eigen::Vector3d q = p - center;
        const double h = q.dot(axis);
        if (h < -tol || h > length + tol) return false;
        const Eigen::Vector3d w = q - h * axis;
        const Eigen::Vector3d v = axis.cross(u);
        double phi = std::atan2(w.dot(v), w.dot(u));
        if (angle < 0) phi = -phi;
        if (phi < 0) phi += 2 * kPi;
        double dist;
        if (std::abs(angle) >= 2 * kPi - 1e-9 || phi <= std::abs(angle)) {
          dist = std::abs(w.norm() - rho0);
        } else {
          const double ea = angle;
          const Eigen::Vector3d end_dir = std::cos(ea) * u + std::sin(ea) * v;
          dist = std::min((w - rho0 * u).norm(), (w - rho0 * end_dir).norm());
        }
        return dist <= r + tol;
      }
    }
    return false;
  }
};

class Checker {
 public:
  Checker(const testpieces::TestPiece& piece, const IrProgram& prog, const PostedText& posted,
          const StockEnvelope& stock, const SafetyOptions& o)
      : piece_(piece), prog_(prog), posted_(posted), stock_(stock), o_(o) {
    report_.min_rapid_clearance_mm = std::numeric_limits<double>::infinity();
  }

  Result<SafetyReport> Run() {
    int tool = -1;
    for (std::size_t i = 0; i < prog_.instrs.size(); ++i) {
      const Instr& in = prog_.instrs[i];
      const int idx = static_cast<int>(i);
      ++report_.instructions_checked;
      if (in.kind == InstrKind::kToolChange) tool = in.tool_index;
      if (o_.check_strokes) TPCAL_RETURN_IF_ERROR(Strokes(in, idx));
      if (o_.check_rapids && tool >= 0) {
        const ToolShape shape = ShapeOf(prog_.tools[tool].tool);
        if ((in.kind == InstrKind::kRapid && in.axis_mask == 0x3F) || in.kind == InstrKind::kIndex) {
          TPCAL_RETURN_IF_ERROR(Rapid(in.start, in.end, shape, idx, prog_.tools[tool]));
        } else if (in.kind == InstrKind::kDrillCycle) {
          AxisState a = in.start, r = in.start, bottom = in.start;
          a.x_mm = r.x_mm = bottom.x_mm = in.drill.x_mm;
          a.y_mm = r.y_mm = bottom.y_mm = in.drill.y_mm;
          r.z_mm = in.drill.r_z_mm;
          bottom.z_mm = in.drill.bottom_z_mm;
          TPCAL_RETURN_IF_ERROR(Rapid(in.start, a, shape, idx, prog_.tools[tool]));
          TPCAL_RETURN_IF_ERROR(Rapid(a, r, shape, idx, prog_.tools[tool]));
          AddLineSweep(r, bottom, prog_.tools[tool].tool);
          TPCAL_RETURN_IF_ERROR(Rapid(r, in.end, shape, idx, prog_.tools[tool]));
        }
      }
      if (tool >= 0 && (in.kind == InstrKind::kLinear || in.kind == InstrKind::kArc)) AddSweeps(in, prog_.tools[tool].tool);
    }
    if (o_.check_tool_fit) TPCAL_RETURN_IF_ERROR(ToolFit());
    if (!std::isfinite(report_.min_rapid_clearance_mm)) report_.min_rapid_clearance_mm = 0.0;
    return report_;
  }

 private:
  Status StrokeAt(const AxisState& s, int idx, const std::string& what) {
    const Status st = kinematics::CheckStrokes(piece_.machine, s);
    if (!st.ok()) return Violation(posted_, idx, what + " outside the machine's travel: " + st.message());
    return Status::Ok();
  }

  Status Strokes(const Instr& in, int idx) {
    switch (in.kind) {
      case InstrKind::kRapid:
      case InstrKind::kIndex:
      case InstrKind::kLinear:
        return StrokeAt(in.end, idx, std::string(InstrKindName(in.kind)) + " target");
      case InstrKind::kArc: {
        const Eigen::Vector2d r0(in.start.x_mm - in.arc_center_xy_mm.x(), in.start.y_mm - in.arc_center_xy_mm.y());
        const int n = std::max(4, static_cast<int>(std::ceil(RadToDeg(in.arc_angle_rad))));
        for (int k = 0; k <= n; ++k) {
          const double a = (in.clockwise ? -1.0 : 1.0) * in.arc_angle_rad * k / n;
          AxisState s = in.start;
          s.x_mm = in.arc_center_xy_mm.x() + std::cos(a) * r0.x() - std::sin(a) * r0.y();
          s.y_mm = in.arc_center_xy_mm.y() + std::sin(a) * r0.x() + std::cos(a) * r0.y();
          TPCAL_RETURN_IF_ERROR(StrokeAt(s, idx, "arc"));
        }
        return Status::Ok();
      }
      case InstrKind::kDrillCycle: {
        AxisState s = in.start;
        s.x_mm = in.drill.x_mm;
        s.y_mm = in.drill.y_mm;
        s.z_mm = in.drill.bottom_z_mm;
        TPCAL_RETURN_IF_ERROR(StrokeAt(s, idx, "cycle bottom"));
        return StrokeAt(in.end, idx, "cycle return");
      }
      default:
        return Status::Ok();
    }
  }

  Status Rapid(const AxisState& from, const AxisState& to, const ToolShape& shape, int idx, const IrTool& tool) {
    ++report_.rapids_checked;
    const double lin = std::max({std::abs(to.x_mm - from.x_mm), std::abs(to.y_mm - from.y_mm), std::abs(to.z_mm - from.z_mm)});
    const double rot = RadToDeg(std::max({std::abs(to.a_rad - from.a_rad), std::abs(to.b_rad - from.b_rad),
                                          std::abs(to.c_rad - from.c_rad)}));
    const int n = std::max(1, static_cast<int>(std::ceil(std::max(lin / o_.rapid_sample_mm, rot))));
    for (int k = 0; k <= n; ++k) {
      const AxisState s = Lerp(from, to, static_cast<double>(k) / n);
      const Rigid3 part_from_tool = kinematics::NominalPartFromTool(piece_.machine, s);
      ++report_.rapid_samples;
      for (const Eigen::Vector3d& q : shape.points) {
        const Eigen::Vector3d p = part_from_tool * q;
        std::string nearest;
        const double d = stock_.SignedDistance(p, &nearest);
        if (d < o_.rapid_tolerance_mm && Removed(p)) continue;  // cut away by an earlier feed
        if (d < report_.min_rapid_clearance_mm) {
          report_.min_rapid_clearance_mm = d;
          report_.min_rapid_block = LabelOf(posted_, idx);
        }
        if (d < -o_.rapid_tolerance_mm) {
          return Violation(posted_, idx,
                           "rapid move enters the stock envelope ('" + nearest + "') by " + Mm(-d) + " mm with tool T" +
                               std::to_string(tool.number) + " (" + tool.tool.name + ") at part (" + Mm(p.x()) + ", " +
                               Mm(p.y()) + ", " + Mm(p.z()) + ") mm; axes " + kinematics::ToString(s));
        }
      }
    }
    return Status::Ok();
  }

  bool Removed(const Eigen::Vector3d& p) const {
    for (auto it = sweeps_.rbegin(); it != sweeps_.rend(); ++it) {
      if (it->Contains(p, o_.rapid_tolerance_mm)) return true;
    }
    return false;
  }

  double CuttingLength(const testpieces::Tool& t) const {
    return t.flute_length_mm > 0 ? t.flute_length_mm : std::max(t.diameter_mm, 1.0);
  }

  void AddLineSweep(const AxisState& from, const AxisState& to, const testpieces::Tool& t) {
    Sweep s;
    s.kind = Sweep::Kind::kLine;
    s.tip0 = kinematics::NominalToolPointInPart(piece_.machine, from, Eigen::Vector3d::Zero());
    s.d = kinematics::NominalToolPointInPart(piece_.machine, to, Eigen::Vector3d::Zero()) - s.tip0;
    s.axis = kinematics::NominalToolAxisInPart(piece_.machine, Lerp(from, to, 0.5));
    s.r = t.radius_mm();
    s.length = CuttingLength(t);
    sweeps_.push_back(s);
  }

  // The volume a feed move removes (part frame).
  void AddSweeps(const Instr& in, const testpieces::Tool& t) {
    if (in.kind == InstrKind::kLinear && in.feed_mode == FeedMode::kPerRevolution) {
      // Table turning: the nose sweeps a solid of revolution about the C axis.
      Sweep s;
      s.kind = Sweep::Kind::kTurn;
      const Eigen::Vector3d p0 = kinematics::NominalToolPointInPart(piece_.machine, in.start, Eigen::Vector3d::Zero());
      const Eigen::Vector3d p1 = kinematics::NominalToolPointInPart(piece_.machine, in.end, Eigen::Vector3d::Zero());
      s.a = Eigen::Vector2d(std::hypot(p0.x(), p0.y()), p0.z());
      s.b = Eigen::Vector2d(std::hypot(p1.x(), p1.y()), p1.z());
      s.r = t.kind == testpieces::ToolKind::kTurningInsert ? t.corner_radius_mm : t.radius_mm();
      sweeps_.push_back(s);
      return;
    }
    if (in.kind == InstrKind::kArc) {
      Sweep s;
      s.kind = Sweep::Kind::kArc;
      AxisState c = in.start;
      c.x_mm = in.arc_center_xy_mm.x();
      c.y_mm = in.arc_center_xy_mm.y();
      s.center = kinematics::NominalToolPointInPart(piece_.machine, c, Eigen::Vector3d::Zero());
      const Eigen::Vector3d tip = kinematics::NominalToolPointInPart(piece_.machine, in.start, Eigen::Vector3d::Zero());
      s.axis = kinematics::NominalToolAxisInPart(piece_.machine, in.start);
      s.rho0 = (tip - s.center).norm();
      s.u = s.rho0 > 0 ? Eigen::Vector3d((tip - s.center) / s.rho0) : Eigen::Vector3d::UnitX();
      s.angle = in.clockwise ? -in.arc_angle_rad : in.arc_angle_rad;
      s.r = t.radius_mm();
      s.length = CuttingLength(t);
      sweeps_.push_back(s);
      return;
    }
    // Straight feed; with rotary motion, joint-interpolated sub-steps of at most 0.5 deg.
    const double rot = RadToDeg(std::max({std::abs(in.end.a_rad - in.start.a_rad), std::abs(in.end.b_rad - in.start.b_rad),
                                          std::abs(in.end.c_rad - in.start.c_rad)}));
    const int n = std::max(1, static_cast<int>(std::ceil(rot / 0.5)));
    for (int k = 0; k < n; ++k) {
      AddLineSweep(Lerp(in.start, in.end, static_cast<double>(k) / n), Lerp(in.start, in.end, static_cast<double>(k + 1) / n), t);
    }
  }

  int InstrOf(const testpieces::CutRef& ref) const {
    for (std::size_t i = 0; i < prog_.instrs.size(); ++i) {
      const Instr& in = prog_.instrs[i];
      if (in.op == ref.op && in.pass == ref.pass && in.move == ref.move) return static_cast<int>(i);
    }
    for (std::size_t i = 0; i < prog_.instrs.size(); ++i) {
      if (prog_.instrs[i].op == ref.op) return static_cast<int>(i);
    }
    return 0;
  }

  const testpieces::Tool& ToolOfOp(int op) const { return piece_.operations.at(op - 1).tool; }

  Status ToolFit() {
    for (std::size_t f = 0; f < piece_.features.size(); ++f) {
      const testpieces::NominalFeature& feat = piece_.features[f];
      const testpieces::CutModel& model = piece_.cuts[f].model;
      if (const auto* plunge = std::get_if<testpieces::PlungeCut>(&model)) {
        ++report_.tool_fits_checked;
        const testpieces::Tool& t = ToolOfOp(plunge->ref.op);
        const double hole_d = 2.0 * feat.radius_mm;
        if (t.kind == testpieces::ToolKind::kReamer && std::abs(t.diameter_mm - hole_d) > o_.tool_fit_tol_mm) {
          return Violation(posted_, InstrOf(plunge->ref),
                           "reamer " + t.name + " (D " + Mm(t.diameter_mm) + " mm) does not match hole " + feat.name +
                               " (D " + Mm(hole_d) + " mm)");
        }
        if (t.radius_mm() > feat.radius_mm + o_.tool_fit_tol_mm) {
          return Violation(posted_, InstrOf(plunge->ref), "tool " + t.name + " is larger than hole " + feat.name);
        }
      } else if (const auto* mill = std::get_if<testpieces::PathMillCut>(&model)) {
        if (mill->end_face || mill->elements.empty()) continue;
        if (feat.type == testpieces::SurfaceType::kCylinder && feat.internal) {
          ++report_.tool_fits_checked;
          if (!(mill->tool_radius_mm < feat.radius_mm)) {
            return Violation(posted_, InstrOf(mill->elements.front().ref),
                             "end mill radius " + Mm(mill->tool_radius_mm) + " mm does not fit the concave face " +
                                 feat.name + " (radius " + Mm(feat.radius_mm) + " mm)");
          }
        }
      }
    }
    if (piece_.kind() == testpieces::PieceKind::kTurning) {
      const auto& p = std::get<testpieces::TurningPieceParams>(piece_.config.params);
      const testpieces::FeatureCut* sr = piece_.Cut("S_R");
      const auto* mill = sr ? std::get_if<testpieces::PathMillCut>(&sr->model) : nullptr;
      if (mill && !mill->elements.empty()) {
        ++report_.tool_fits_checked;
        const double width = p.groove_outer_radius_mm - p.groove_inner_radius_mm;
        if (mill->tool_radius_mm > 0.5 * width) {
          return Violation(posted_, InstrOf(mill->elements.front().ref),
                           "end mill radius " + Mm(mill->tool_radius_mm) + " mm exceeds half the groove width (" +
                               Mm(0.5 * width) + " mm)");
        }
      }
    }
    return Status::Ok();
  }

  const testpieces::TestPiece& piece_;
  const IrProgram& prog_;
  const PostedText& posted_;
  const StockEnvelope& stock_;
  const SafetyOptions& o_;
  SafetyReport report_;
  std::vector<Sweep> sweeps_;
};

}  // namespace

Result<SafetyReport> CheckProgram(const testpieces::TestPiece& piece, const IrProgram& prog, const PostedText& posted,
                                  const StockEnvelope& stock, const SafetyOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  Checker c(piece, prog, posted, stock, options);
  return c.Run();
}

}  // namespace tpcal::gcode
