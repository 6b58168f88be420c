#include "gcode/nc_path.h"

#include <cmath>
#include <sstream>

#include "core/units.h"
#include "kinematics/forward_kinematics.h"

namespace tpcal::gcode {
namespace {

std::array<double, 6> Axes(const kinematics::AxisState& s) {
  return {s.x_mm, s.y_mm, s.z_mm, RadToDeg(s.a_rad), RadToDeg(s.b_rad), RadToDeg(s.c_rad)};
}

kinematics::AxisState State(const std::array<double, 6>& v) {
  kinematics::AxisState s;
  s.x_mm = v[0];
  s.y_mm = v[1];
  s.z_mm = v[2];
  s.a_rad = DegToRad(v[3]);
  s.b_rad = DegToRad(v[4]);
  s.c_rad = DegToRad(v[5]);
  return s;
}

std::string Fmt(double v) {
  std::ostringstream os;
  os.precision(6);
  os << v;
  return os.str();
}

}  // namespace

const char* PathMoveKindName(PathMoveKind k) {
  switch (k) {
    case PathMoveKind::kRapid: return "rapid";
    case PathMoveKind::kFeed: return "feed";
    case PathMoveKind::kArc: return "arc";
  }
  return "?";
}

NcPath ExpectedPath(const IrProgram& prog) {
  NcPath path;
  std::array<double, 6> cur{};
  auto add = [&](PathMoveKind kind, const std::array<double, 6>& end) {
    PathMove m;
    m.kind = kind;
    m.end = end;
    path.moves.push_back(m);
    cur = end;
  };
  for (const Instr& in : prog.instrs) {
    switch (in.kind) {
      case InstrKind::kToolChange:
        ++path.tool_changes;
        break;
      case InstrKind::kRapid:
      case InstrKind::kIndex: {
        std::array<double, 6> end = cur;
        const auto target = Axes(in.end);
        for (int i = 0; i < 6; ++i) {
          if (in.axis_mask & (1u << i)) end[i] = target[i];
        }
        add(PathMoveKind::kRapid, end);
        break;
      }
      case InstrKind::kLinear:
      case InstrKind::kProbe:  // as far as the target when nothing is touched (rs274's STRAIGHT_PROBE)
        add(PathMoveKind::kFeed, Axes(in.end));
        break;
      case InstrKind::kArc: {
        PathMove m;
        m.kind = PathMoveKind::kArc;
        m.end = Axes(in.end);
        m.plane = 17;
        m.center1_mm = in.arc_center_xy_mm.x();
        m.center2_mm = in.arc_center_xy_mm.y();
        m.rotation = in.clockwise ? -1 : 1;
        path.moves.push_back(m);
        cur = m.end;
        break;
      }
      case InstrKind::kDrillCycle: {
        const DrillCycle& d = in.drill;
        std::array<double, 6> p = cur;
        p[0] = d.x_mm;
        p[1] = d.y_mm;
        add(PathMoveKind::kRapid, p);
        const double initial = p[2];
        p[2] = d.r_z_mm;
        add(PathMoveKind::kRapid, p);
        p[2] = d.bottom_z_mm;
        add(PathMoveKind::kFeed, p);
        p[2] = d.r_z_mm;
        add(PathMoveKind::kFeed, p);
        if (d.return_to_initial) {
          p[2] = initial;
          add(PathMoveKind::kRapid, p);
        }
        break;
      }
      default:
        break;
    }
  }
  return path;
}

std::vector<PartPoint> ToPartPoints(const NcPath& path, const kinematics::MachineModel& machine, double merge_tol_mm) {
  std::vector<PartPoint> out;
  for (const PathMove& m : path.moves) {
    PartPoint p;
    p.kind = m.kind;
    p.label = m.label;
    p.a_deg = m.end[3];
    p.b_deg = m.end[4];
    p.c_deg = m.end[5];
    const kinematics::AxisState s = State(m.end);
    p.tip_mm = m.tcp ? Eigen::Vector3d(m.end[0], m.end[1], m.end[2])
                     : kinematics::NominalToolPointInPart(machine, s, Eigen::Vector3d::Zero());
    if (m.kind == PathMoveKind::kArc) {
      kinematics::AxisState c = s;
      if (m.plane == 17) {
        c.x_mm = m.center1_mm;
        c.y_mm = m.center2_mm;
      } else if (m.plane == 18) {
        c.z_mm = m.center1_mm;
        c.x_mm = m.center2_mm;
      } else {
        c.y_mm = m.center1_mm;
        c.z_mm = m.center2_mm;
      }
      p.arc_center_mm = kinematics::NominalToolPointInPart(machine, c, Eigen::Vector3d::Zero());
      p.rotation = m.rotation;
    }
    auto rotary_equal = [](const PartPoint& x, const PartPoint& y) {
      return std::abs(x.a_deg - y.a_deg) < 1e-9 && std::abs(x.b_deg - y.b_deg) < 1e-9 && std::abs(x.c_deg - y.c_deg) < 1e-9;
    };
    if (p.kind != PathMoveKind::kArc && !out.empty() && rotary_equal(p, out.back()) &&
        (p.tip_mm - out.back().tip_mm).norm() < 1e-7) {
      continue;  // no motion
    }
    // Merge with the previous straight move of the same kind when collinear, same direction,
    // and no rotary motion in either.
    if (p.kind != PathMoveKind::kArc && out.size() >= 2 && out.back().kind == p.kind && rotary_equal(p, out.back()) &&
        rotary_equal(p, out[out.size() - 2])) {
      const Eigen::Vector3d u = out.back().tip_mm - out[out.size() - 2].tip_mm, v = p.tip_mm - out.back().tip_mm;
      if (u.norm() > 0 && v.norm() > 0 && u.dot(v) > 0 && u.normalized().cross(v).norm() < merge_tol_mm) {
        out.back().tip_mm = p.tip_mm;
        out.back().label = p.label;
        continue;
      }
    }
    out.push_back(p);
  }
  return out;
}

Result<PathComparison> ComparePaths(const std::vector<PartPoint>& ref, const std::vector<PartPoint>& other, double tol_mm,
                                    double tol_deg) {
  PathComparison c;
  const std::size_t n = std::min(ref.size(), other.size());
  for (std::size_t i = 0; i < n; ++i) {
    const PartPoint& a = ref[i];
    const PartPoint& b = other[i];
    const std::string where = "point " + std::to_string(i) + " (" + (a.label.empty() ? "?" : a.label) + " vs " +
                              (b.label.empty() ? "?" : b.label) + ")";
    if (a.kind != b.kind) {
      return Status(StatusCode::kInvalidArgument, where + ": " + PathMoveKindName(a.kind) + " vs " + PathMoveKindName(b.kind));
    }
    const double dt = (a.tip_mm - b.tip_mm).norm();
    const double dr = std::max({std::abs(a.a_deg - b.a_deg), std::abs(a.b_deg - b.b_deg), std::abs(a.c_deg - b.c_deg)});
    if (dt > c.max_tip_deviation_mm) {
      c.max_tip_deviation_mm = dt;
      c.worst_label = b.label;
    }
    c.max_rotary_deviation_deg = std::max(c.max_rotary_deviation_deg, dr);
    if (a.kind == PathMoveKind::kArc) {
      if (a.rotation != b.rotation) {
        return Status(StatusCode::kInvalidArgument, where + ": arc rotation " + std::to_string(a.rotation) + " vs " +
                                                        std::to_string(b.rotation));
      }
      c.max_center_deviation_mm = std::max(c.max_center_deviation_mm, (a.arc_center_mm - b.arc_center_mm).norm());
    }
    if (dt > tol_mm || dr > tol_deg || c.max_center_deviation_mm > tol_mm) {
      return Status(StatusCode::kInvalidArgument,
                    where + ": tool point deviates by " + Fmt(dt * 1000.0) + " um (" + Fmt(a.tip_mm.x()) + ", " +
                        Fmt(a.tip_mm.y()) + ", " + Fmt(a.tip_mm.z()) + ") vs (" + Fmt(b.tip_mm.x()) + ", " +
                        Fmt(b.tip_mm.y()) + ", " + Fmt(b.tip_mm.z()) + "), rotary by " + Fmt(dr) + " deg, arc centre by " +
                        Fmt(c.max_center_deviation_mm * 1000.0) + " um");
    }
    ++c.points;
  }
  if (ref.size() != other.size()) {
    const std::size_t i = n;
    const std::string l = i < ref.size() ? ref[i].label : (i < other.size() ? other[i].label : "");
    return Status(StatusCode::kInvalidArgument, "paths differ in length: " + std::to_string(ref.size()) + " vs " +
                                                    std::to_string(other.size()) + " points (first extra at " + l + ")");
  }
  return c;
}

}  // namespace tpcal::gcode
