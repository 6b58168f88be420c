#include "testpieces/turning_piece.h"

#include <cmath>
#include <sstream>

#include "core/units.h"
#include "testpieces/internal/planning.h"

namespace tpcal::testpieces {
namespace {

constexpr double kMinClearance_mm = 0.5;  // tool-to-stock clearance accepted as collision free

Status Bad(const std::string& key, double value, const std::string& why) {
  std::ostringstream os;
  os << "turning." << key << " = " << value << ": " << why;
  return {StatusCode::kInvalidArgument, os.str()};
}

std::string StepKey(int i, const char* field) { return "steps[" + std::to_string(i) + "]." + field; }

// Part azimuth of the turning tool and the A position of each step (seed 002 section 2.1):
// S1, S4 at A = 0 with the tool at +X; S2, S5 at A = 0 with the tool at +Y (X = 0); S3, S6 at
// A = -90 with the tool above the part (machine +Z), which is part +Y at C = 0.
struct StepSetup {
  double a_rad;
  double tool_azimuth_rad;
  const char* where;
};
StepSetup SetupOf(int i) {
  switch (i % 3) {
    case 0: return {0.0, 0.0, "A = 0, tool at +X (Y = 0), B by -X feed, S by -Z feed"};
    case 1: return {0.0, kPi / 2, "A = 0, tool at +Y (X = 0), B by -Y feed, S by -Z feed"};
    default: return {-kPi / 2, kPi / 2, "A = -90 deg, tool above the part (X = 0), B by -Z feed, S by +Y feed"};
  }
}

}  // namespace

double TurningPieceParams::BottomOuterRadius(int i) const {
  return i + 1 < static_cast<int>(steps.size()) ? steps[i + 1].radius_mm : base_radius_mm;
}

Status TurningPieceParams::Validate() const {
  auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  struct Named { const char* key; double value; };
  for (const Named& n : {Named{"groove.depth_mm", groove_depth_mm}, Named{"groove.outer_radius_mm", groove_outer_radius_mm},
                         Named{"groove.inner_radius_mm", groove_inner_radius_mm},
                         Named{"groove.wall_probe_height_mm", groove_wall_probe_height_mm},
                         Named{"groove.floor_probe_radius_mm", groove_floor_probe_radius_mm},
                         Named{"groove.finish_stock_mm", groove_finish_stock_mm},
                         Named{"groove.wall_lift_mm", groove_wall_lift_mm},
                         Named{"holes.pitch_radius_mm", hole_pitch_radius_mm}, Named{"holes.depth_mm", hole_depth_mm},
                         Named{"holes.probe_depth_mm", hole_probe_depth_mm}, Named{"base.radius_mm", base_radius_mm},
                         Named{"end_mill.diameter_mm", end_mill_diameter_mm},
                         Named{"end_mill.floor_cutting_speed_m_per_min", floor_cutting_speed_m_per_min},
                         Named{"end_mill.floor_feed_per_tooth_mm", floor_feed_per_tooth_mm},
                         Named{"end_mill.wall_cutting_speed_m_per_min", wall_cutting_speed_m_per_min},
                         Named{"end_mill.wall_feed_per_tooth_mm", wall_feed_per_tooth_mm},
                         Named{"reamer.diameter_mm", reamer_diameter_mm},
                         Named{"reamer.cutting_speed_m_per_min", reamer_cutting_speed_m_per_min},
                         Named{"reamer.feed_per_tooth_mm", reamer_feed_per_tooth_mm},
                         Named{"turning_tool.nose_radius_mm", insert_nose_radius_mm},
                         Named{"turning_tool.included_angle_deg", insert_included_angle_deg},
                         Named{"turning_tool.cutting_speed_m_per_min", turning_cutting_speed_m_per_min},
                         Named{"turning_tool.feed_mm_per_rev", turning_feed_mm_per_rev},
                         Named{"turning_tool.depth_of_cut_mm", turning_depth_of_cut_mm},
                         Named{"turning_tool.max_table_rpm", turning_max_table_rpm},
                         Named{"turning_tool.reach_mm", turning_tool_reach_mm},
                         Named{"turning_tool.shank_width_mm", turning_shank_width_mm},
                         Named{"approach_clearance_mm", approach_clearance_mm},
                         Named{"safe_clearance_mm", safe_clearance_mm}}) {
    if (!positive(n.value)) return Bad(n.key, n.value, "must be a positive number");
  }
  for (const Named& n : {Named{"groove.bottom_z_mm", groove_bottom_z_mm}, Named{"base.bottom_z_mm", base_bottom_z_mm},
                         Named{"base.bore_radius_mm", bore_radius_mm}, Named{"base.bore_top_z_mm", bore_top_z_mm},
                         Named{"end_mill.corner_radius_mm", end_mill_corner_radius_mm},
                         Named{"bottom_probe_fraction", bottom_probe_fraction}}) {
    if (!std::isfinite(n.value)) return Bad(n.key, n.value, "must be a finite number");
  }
  if (end_mill_teeth < 1) return Bad("end_mill.teeth", end_mill_teeth, "must be >= 1");
  if (reamer_teeth < 1) return Bad("reamer.teeth", reamer_teeth, "must be >= 1");
  if (hole_count < 3) return Bad("holes.count", hole_count, "a pitch circle needs at least 3 holes");
  if (!(insert_included_angle_deg < 180.0)) {
    return Bad("turning_tool.included_angle_deg", insert_included_angle_deg, "must be < 180");
  }
  if (!(bottom_probe_fraction > 0 && bottom_probe_fraction < 1)) {
    return Bad("bottom_probe_fraction", bottom_probe_fraction, "must be in (0, 1)");
  }
  const double rt = 0.5 * end_mill_diameter_mm;
  const double rc = end_mill_corner_radius_mm;
  const double rn = insert_nose_radius_mm;
  const double doc = turning_depth_of_cut_mm;
  if (!(rc >= 0 && rc < rt)) return Bad("end_mill.corner_radius_mm", rc, "must be in [0, tool radius)");

  // Groove: wider than the tool, inside S1, clear of the holes and the bore.
  const double width = groove_outer_radius_mm - groove_inner_radius_mm;
  if (!(width > end_mill_diameter_mm + 2 * groove_finish_stock_mm)) {
    return Bad("groove.inner_radius_mm", groove_inner_radius_mm,
               "groove must be wider than the end mill plus the finishing stock on both walls");
  }
  const double hole_r = 0.5 * reamer_diameter_mm;
  if (!(groove_outer_radius_mm + 1.0 < hole_pitch_radius_mm - hole_r)) {
    return Bad("groove.outer_radius_mm", groove_outer_radius_mm, "groove must end 1 mm inside the holes");
  }
  if (!(hole_pitch_radius_mm + hole_r + 1.0 < steps[0].radius_mm)) {
    return Bad("holes.pitch_radius_mm", hole_pitch_radius_mm, "holes must end 1 mm inside S1");
  }
  if (2 * kPi * hole_pitch_radius_mm / hole_count < reamer_diameter_mm + 1.0) {
    return Bad("holes.count", hole_count, "holes overlap on the pitch circle");
  }
  if (!(groove_wall_probe_height_mm > groove_wall_lift_mm + rc + 0.2 &&
        groove_wall_probe_height_mm < groove_depth_mm - 0.2)) {
    return Bad("groove.wall_probe_height_mm", groove_wall_probe_height_mm,
               "S_R probing height must lie on the wall pass's flank, below the top face");
  }
  {
    // B_R is probed under the flat end of the last floor circle.
    const double r_last = groove_outer_radius_mm - groove_finish_stock_mm - rt;
    if (!(std::abs(groove_floor_probe_radius_mm - r_last) < rt - rc - 0.2)) {
      return Bad("groove.floor_probe_radius_mm", groove_floor_probe_radius_mm,
                 "B_R probing radius must lie under the flat end of the last floor pass");
    }
  }
  if (!(hole_probe_depth_mm > 1.0 && hole_probe_depth_mm < hole_depth_mm - 1.0)) {
    return Bad("holes.probe_depth_mm", hole_probe_depth_mm, "must be at least 1 mm from both hole ends");
  }

  // Steps: radii increasing downward, heights decreasing, probing heights on the faces.
  double section_top = top_z_mm();
  for (int i = 0; i < 6; ++i) {
    const TurnedStep& s = steps[i];
    if (!positive(s.radius_mm)) return Bad(StepKey(i, "radius_mm"), s.radius_mm, "must be a positive number");
    if (!(s.shoulder_z_mm < section_top - 1.0)) {
      return Bad(StepKey(i, "shoulder_z_mm"), s.shoulder_z_mm, "each shoulder must lie > 1 mm below the one above");
    }
    if (!(s.probe_z_mm > s.shoulder_z_mm + rn + 0.2 && s.probe_z_mm < section_top - 0.2)) {
      return Bad(StepKey(i, "probe_z_mm"), s.probe_z_mm, "S probing height must lie on the face above the nose radius");
    }
    const double r_out = BottomOuterRadius(i);
    if (!(r_out > s.radius_mm + rn + 1.0)) {
      // Also the machinability rule for the face below: with radii growing downward, a vertical
      // tool reaching a lower face never meets the faces above it (checked again below).
      const std::string below = i + 1 < 6 ? "S" + std::to_string(i + 2) : "the base flange";
      return Bad(i + 1 < 6 ? StepKey(i + 1, "radius_mm") : std::string("base.radius_mm"), r_out,
                 "must exceed S" + std::to_string(i + 1) + "'s radius " + std::to_string(s.radius_mm) +
                     " mm by more than the nose radius + 1 mm: B" + std::to_string(i + 1) +
                     " needs width, and a vertical turning tool reaching " + below + " from above would hit S" +
                     std::to_string(i + 1));
    }
    const double probe_r = s.radius_mm + bottom_probe_fraction * (r_out - s.radius_mm);
    if (!(probe_r > s.radius_mm + rn + 0.2 && probe_r < r_out - 0.2)) {
      return Bad("bottom_probe_fraction", bottom_probe_fraction,
                 "B" + std::to_string(i + 1) + " probing circle falls on the nose fillet or the edge");
    }
    section_top = s.shoulder_z_mm;
  }
  if (!(base_bottom_z_mm < steps[5].shoulder_z_mm - 1.0)) {
    return Bad("base.bottom_z_mm", base_bottom_z_mm, "must lie below B6");
  }
  if (!(steps[0].radius_mm > groove_outer_radius_mm)) {
    return Bad(StepKey(0, "radius_mm"), steps[0].radius_mm, "S1 must lie outside the groove");
  }
  if (bore_radius_mm > 0) {
    if (!(bore_radius_mm < groove_inner_radius_mm - 1.0)) {
      return Bad("base.bore_radius_mm", bore_radius_mm, "bore must lie inside the groove");
    }
    if (!(bore_top_z_mm > base_bottom_z_mm && bore_top_z_mm < groove_bottom_z_mm - 5.0 &&
          bore_top_z_mm < top_z_mm() - hole_depth_mm - 5.0)) {
      return Bad("base.bore_top_z_mm", bore_top_z_mm, "bore must end 5 mm below the groove and the holes");
    }
  }

  // Machinability of the turned faces (README "Machinability").
  for (int i = 0; i < 6; ++i) {
    const TurnedStep& s = steps[i];
    const StepSetup setup = SetupOf(i);
    if (setup.a_rad == 0.0) {
      // A vertical tool reaching down to B_i: everything above (with stock) at a smaller radius.
      for (int j = 0; j < i; ++j) {
        if (!(steps[j].radius_mm + doc + kMinClearance_mm <= s.radius_mm)) {
          return Bad(StepKey(i, "radius_mm"), s.radius_mm,
                     "the A = 0 turning tool reaching S" + std::to_string(i + 1) + " would hit S" +
                         std::to_string(j + 1) + " above it (its radius with stock is not smaller)");
        }
      }
      const double reach = top_z_mm() + doc + approach_clearance_mm - s.shoulder_z_mm;
      if (reach > turning_tool_reach_mm) {
        return Bad("turning_tool.reach_mm", turning_tool_reach_mm,
                   "too short to reach B" + std::to_string(i + 1) + " (needs " + std::to_string(reach) + " mm)");
      }
    } else {
      // A radial tool at A = -90: the shank (width along part Z above B_i) clears the sections.
      const double z_lo = s.shoulder_z_mm;
      const double z_hi = s.shoulder_z_mm + turning_shank_width_mm;
      double top = top_z_mm();
      for (int j = 0; j < i; ++j) {
        const double bottom = steps[j].shoulder_z_mm;
        if (bottom < z_hi && top > z_lo && !(steps[j].radius_mm + doc + kMinClearance_mm <= s.radius_mm)) {
          return Bad("turning_tool.shank_width_mm", turning_shank_width_mm,
                     "the A = -90 shank cutting S" + std::to_string(i + 1) + " would hit S" + std::to_string(j + 1));
        }
        top = bottom;
      }
    }
  }
  return Status::Ok();
}

namespace internal {
namespace {

struct TurningBuild {
  const TurningPieceParams& p;
  const kinematics::MachineModel& machine;
  ProgramBuilder program;
  TestPiece piece;
  double z_safe_mm = 0;  // machine Z above the part in every setup

  TurningBuild(const TurningPieceParams& params, const PieceConfig& config, const kinematics::MachineModel& m)
      : p(params), machine(m), program(config.process) {}

  static kinematics::AxisState Rot(double a, double c) {
    kinematics::AxisState s;
    s.a_rad = a;
    s.c_rad = c;
    return s;
  }

  Result<kinematics::AxisState> At(const Eigen::Vector3d& ref_part, double a, double c) {
    return AxesForRefPoint(machine, ref_part, Rot(a, c), true);
  }

  // Rapid retract to the safe Z, index the rotary axes, then rapid to `target`'s X, Y and down.
  void Reposition(const kinematics::AxisState& target) {
    kinematics::AxisState s = program.state();
    const bool rotary_change = s.a_rad != target.a_rad || s.c_rad != target.c_rad;
    if (rotary_change || std::abs(s.x_mm - target.x_mm) + std::abs(s.y_mm - target.y_mm) > 1e-9) {
      if (s.z_mm < z_safe_mm) {
        s.z_mm = z_safe_mm;
        program.Rapid(s);
      }
      if (rotary_change) {
        s.a_rad = target.a_rad;
        s.c_rad = target.c_rad;
        program.Rapid(s);
      }
      s.x_mm = target.x_mm;
      s.y_mm = target.y_mm;
      program.Rapid(s);
    }
    program.Rapid(target);
  }
  void RetractToSafe() {
    kinematics::AxisState s = program.state();
    if (s.z_mm < z_safe_mm) {
      s.z_mm = z_safe_mm;
      program.Rapid(s);
    }
  }

  Tool EndMill() const {
    Tool t;
    t.number = 1;
    t.kind = ToolKind::kEndMill;
    t.diameter_mm = p.end_mill_diameter_mm;
    t.corner_radius_mm = p.end_mill_corner_radius_mm;
    t.teeth = p.end_mill_teeth;
    t.flute_length_mm = 2.5 * p.end_mill_diameter_mm;
    t.material = "coated carbide";
    std::ostringstream os;
    os << "radius end mill d" << p.end_mill_diameter_mm << " R" << p.end_mill_corner_radius_mm;
    t.name = os.str();
    return t;
  }
  Tool Reamer() const {
    Tool t;
    t.number = 2;
    t.kind = ToolKind::kReamer;
    t.diameter_mm = p.reamer_diameter_mm;
    t.teeth = p.reamer_teeth;
    t.flute_length_mm = p.hole_depth_mm + 10.0;
    t.material = "carbide";
    std::ostringstream os;
    os << "reamer d" << p.reamer_diameter_mm;
    t.name = os.str();
    return t;
  }
  Tool Insert() const {
    Tool t;
    t.number = 3;
    t.kind = ToolKind::kTurningInsert;
    t.corner_radius_mm = p.insert_nose_radius_mm;
    t.included_angle_deg = p.insert_included_angle_deg;
    t.gauge_length_mm = p.turning_tool_reach_mm;
    t.material = "carbide";
    std::ostringstream os;
    os << "turning insert " << p.insert_included_angle_deg << " deg r" << p.insert_nose_radius_mm;
    t.name = os.str();
    return t;
  }
  static Spindle Milling(double cutting_speed_m_per_min, double diameter_mm) {
    Spindle s;
    s.mode = SpindleMode::kMilling;
    s.speed_rpm = cutting_speed_m_per_min * 1000.0 / (kPi * diameter_mm);
    return s;
  }

  void AddFeature(NominalFeature f, CutModel cut) {
    piece.cuts.push_back({f.name, std::move(cut)});
    piece.features.push_back(std::move(f));
  }

  // One full circle of the end mill at part height z_tip and tool-centre radius R, CCW or CW,
  // starting at azimuth 0. `lead_mm` != 0: plunge that far inside (toward the centre for an
  // outer wall) and lead in / out radially. Returns the arc element.
  Result<PathElement> Circle(double radius, double z_tip, bool ccw, double feed, double lead_mm) {
    const double a = 0.0, c = 0.0;
    const Eigen::Vector3d start(radius, 0, z_tip);
    const Eigen::Vector3d plunge(radius - lead_mm, 0, z_tip);
    TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState above, At(plunge + Eigen::Vector3d(0, 0, p.top_z_mm() - z_tip + p.approach_clearance_mm), a, c));
    Reposition(above);
    TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState down, At(plunge, a, c));
    program.Linear(down, 0.5 * feed, false);
    if (lead_mm != 0.0) {
      TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState in, At(start, a, c));
      program.Linear(in, feed, true);
    }
    TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState centre, At(Eigen::Vector3d(0, 0, z_tip), a, c));
    program.Arc(Eigen::Vector2d(centre.x_mm, centre.y_mm), 2 * kPi, !ccw, feed, true);
    PathElement e;
    e.ref = {program.current_operation(), program.current_pass_index(), program.last_move_index()};
    e.arc = true;
    e.center_mm = Eigen::Vector3d(0, 0, z_tip);
    e.start_dir = Eigen::Vector3d::UnitX();
    e.radius_mm = radius;
    e.angle_rad = 2 * kPi;
    e.clockwise = !ccw;
    if (lead_mm != 0.0) program.Linear(down, feed, false);
    RetractToSafe();
    return e;
  }

  Status Groove() {
    const double rt = 0.5 * p.end_mill_diameter_mm;
    const double rc = p.end_mill_corner_radius_mm;
    const double z_r = p.groove_bottom_z_mm;
    const double stock = p.groove_finish_stock_mm;
    const Tool tool = EndMill();
    program.BeginOperation("groove", "seed 002 sec. 2.1 step 1: reference circular groove S_R / B_R by X-Y circular "
                                     "interpolation about the MCS origin at A = C = 0", tool);
    const Spindle floor_spindle = Milling(p.floor_cutting_speed_m_per_min, p.end_mill_diameter_mm);
    const Spindle wall_spindle = Milling(p.wall_cutting_speed_m_per_min, p.end_mill_diameter_mm);
    const double floor_feed = p.floor_feed_per_tooth_mm * p.end_mill_teeth * floor_spindle.speed_rpm;
    const double wall_feed = p.wall_feed_per_tooth_mm * p.end_mill_teeth * wall_spindle.speed_rpm;

    // Floor: an inner circle (finishing the inner wall unless it gets its own pass, CW = climb
    // on that wall) and an outer circle leaving `stock` on S_R (CCW).
    program.BeginPass("B_R floor", floor_spindle, {"B_R"});
    const double r_inner = p.groove_inner_radius_mm + rt + (p.groove_inner_wall_pass ? stock : 0.0);
    const double r_outer = p.groove_outer_radius_mm - stock - rt;
    PathMillCut floor;
    floor.rotary = Rot(0, 0);
    floor.tool_axis = Eigen::Vector3d::UnitZ();
    floor.tool_radius_mm = rt;
    floor.corner_radius_mm = rc;
    floor.end_face = true;
    TPCAL_ASSIGN_OR_RETURN(const PathElement e1, Circle(r_inner, z_r, false, floor_feed, 0.0));
    TPCAL_ASSIGN_OR_RETURN(const PathElement e2, Circle(r_outer, z_r, true, floor_feed, 0.0));
    floor.elements = {e1, e2};

    // S_R wall: climb on an outer wall is CCW with M03 (the material on the right of the path).
    program.BeginPass("S_R wall", wall_spindle, {"S_R"});
    const double z_wall = z_r + p.groove_wall_lift_mm;
    TPCAL_ASSIGN_OR_RETURN(const PathElement ew,
                           Circle(p.groove_outer_radius_mm - rt, z_wall, p.groove_outer_wall_ccw, wall_feed, 0.5));
    PathMillCut wall = floor;
    wall.end_face = false;
    wall.elements = {ew};

    PathMillCut inner_wall = floor;
    inner_wall.end_face = false;
    if (p.groove_inner_wall_pass) {
      program.BeginPass("S_RI wall", wall_spindle, {"S_RI"});
      TPCAL_ASSIGN_OR_RETURN(const PathElement ei,
                             Circle(p.groove_inner_radius_mm + rt, z_wall, false, wall_feed, -0.5));
      inner_wall.elements = {ei};
    }

    const double wall_band_lo = z_wall + rc + 0.3;
    NominalFeature sr;
    sr.name = "S_R";
    sr.type = SurfaceType::kCylinder;
    sr.internal = true;
    sr.radius_mm = p.groove_outer_radius_mm;
    sr.h_min_mm = z_r;
    sr.h_max_mm = p.top_z_mm();
    sr.design_levels_mm = {z_r + p.groove_wall_probe_height_mm};
    sr.level_min_mm = wall_band_lo;
    sr.level_max_mm = p.top_z_mm() - 0.3;
    sr.description = "reference groove side face (outer wall, facing the axis), end mill side, A = C = 0";
    AddFeature(sr, wall);

    NominalFeature br;
    br.name = "B_R";
    br.type = SurfaceType::kPlane;
    br.origin_mm = Eigen::Vector3d(0, 0, z_r);
    br.r_min_mm = p.groove_inner_radius_mm;
    br.r_max_mm = p.groove_outer_radius_mm;
    br.design_levels_mm = {p.groove_floor_probe_radius_mm};
    br.level_min_mm = r_inner - (rt - rc) + 0.2;
    br.level_max_mm = r_outer + (rt - rc) - 0.2;
    br.description = "reference groove bottom face, end mill end, A = C = 0 (primary datum)";
    AddFeature(br, floor);

    if (p.groove_inner_wall_pass) {
      NominalFeature sri = sr;
      sri.name = "S_RI";
      sri.internal = false;
      sri.radius_mm = p.groove_inner_radius_mm;
      sri.description = "reference groove inner wall (enrichment: cut CW, opposite to S_R)";
      AddFeature(sri, inner_wall);
    }
    return Status::Ok();
  }

  Status Holes() {
    const Tool tool = Reamer();
    program.BeginOperation("holes", "seed 002 sec. 2.1 step 2: holes H1..Hn reamed at machine (pitch radius, 0), "
                                    "C indexed every 360/n deg, A = 0", tool);
    const Spindle spindle = Milling(p.reamer_cutting_speed_m_per_min, p.reamer_diameter_mm);
    const double feed = p.reamer_feed_per_tooth_mm * p.reamer_teeth * spindle.speed_rpm;
    std::vector<std::string> names;
    for (int k = 0; k < p.hole_count; ++k) names.push_back("H" + std::to_string(k + 1));
    program.BeginPass("ream", spindle, names);
    const double z_top = p.top_z_mm();
    for (int k = 0; k < p.hole_count; ++k) {
      const double c = 2 * kPi * k / p.hole_count;
      const Eigen::Vector3d axis_xy(p.hole_pitch_radius_mm * std::cos(c), p.hole_pitch_radius_mm * std::sin(c), 0);
      const Eigen::Vector3d entry = axis_xy + Eigen::Vector3d(0, 0, z_top);
      TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState above,
                             At(entry + Eigen::Vector3d(0, 0, p.approach_clearance_mm), 0, c));
      Reposition(above);
      TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState bottom, At(entry - Eigen::Vector3d(0, 0, p.hole_depth_mm), 0, c));
      program.Linear(bottom, feed, true);
      PlungeCut cut;
      cut.ref = {program.current_operation(), program.current_pass_index(), program.last_move_index()};
      cut.rotary = Rot(0, c);
      cut.entry_mm = entry;
      cut.axis = Eigen::Vector3d::UnitZ();
      cut.depth_mm = p.hole_depth_mm;
      cut.tool_radius_mm = 0.5 * p.reamer_diameter_mm;
      program.Linear(above, feed, false);  // G85: feed out

      NominalFeature h;
      h.name = names[k];
      h.type = SurfaceType::kCylinder;
      h.internal = true;
      h.hole = true;
      h.origin_mm = axis_xy;
      h.radius_mm = 0.5 * p.reamer_diameter_mm;
      h.h_min_mm = z_top - p.hole_depth_mm;
      h.h_max_mm = z_top;
      h.design_levels_mm = {p.hole_probe_z_mm()};
      h.level_min_mm = z_top - p.hole_depth_mm + 1.0;
      h.level_max_mm = z_top - 1.0;
      std::ostringstream os;
      os << "reamed hole at C = " << RadToDeg(c) << " deg, machine (" << p.hole_pitch_radius_mm << ", 0)";
      h.description = os.str();
      AddFeature(h, cut);
    }
    RetractToSafe();
    return Status::Ok();
  }

  Status TurnStep(int i) {
    const TurnedStep& s = p.steps[i];
    const StepSetup setup = SetupOf(i);
    const double rn = p.insert_nose_radius_mm;
    const double doc = p.turning_depth_of_cut_mm;
    const double cl = p.approach_clearance_mm;
    const double section_top = i == 0 ? p.top_z_mm() : p.steps[i - 1].shoulder_z_mm;
    const double r_out = p.BottomOuterRadius(i);
    const std::string si = "S" + std::to_string(i + 1), bi = "B" + std::to_string(i + 1);
    const double a = setup.a_rad;
    const Eigen::Vector3d er(std::cos(setup.tool_azimuth_rad), std::sin(setup.tool_azimuth_rad), 0);
    const Eigen::Vector3d ez = Eigen::Vector3d::UnitZ();
    auto nose = [&](double radius, double height) -> Eigen::Vector3d { return radius * er + height * ez; };

    program.BeginOperation("turn " + si + "/" + bi,
                           "seed 002 sec. 2.1: turning of " + si + " and " + bi + ", " + setup.where, Insert());
    Spindle spindle;
    spindle.mode = SpindleMode::kTableTurning;
    spindle.surface_speed_m_per_min = p.turning_cutting_speed_m_per_min;
    spindle.max_speed_rpm = p.turning_max_table_rpm;
    const double f = p.turning_feed_mm_per_rev;

    // Bottom face: radial infeed at the nose-centre height z_B + rn, contact radius from outside
    // the stock to r + rn (the nose fillet r .. r + rn is left by the side pass).
    program.BeginPass(bi + " facing", spindle, {bi});
    const double z_b = s.shoulder_z_mm + rn;
    const double rho_start = r_out + doc + cl, rho_end = s.radius_mm + rn;
    TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState b0, At(nose(rho_start, z_b), a, 0));
    TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState b1, At(nose(rho_end, z_b), a, 0));
    Reposition(b0);
    program.TurnLinear(b1, f, rho_start, rho_end, true);
    TurnedCut bcut;
    bcut.ref = {program.current_operation(), program.current_pass_index(), program.last_move_index()};
    bcut.a_rad = a;
    bcut.tool_azimuth_rad = setup.tool_azimuth_rad;
    bcut.nose_radius_mm = rn;
    bcut.radial_feed = true;
    bcut.coord_start_mm = rho_start;
    bcut.coord_end_mm = rho_end;
    // Feed back out along the channel the facing pass just cut (not up through the uncut S_i stock).
    TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState b_out, At(nose(rho_start, z_b), a, 0));
    program.TurnLinear(b_out, f, rho_end, rho_start, false);

    // Side face: axial feed at nose-centre radius r + rn from above the stock down to z_B + rn.
    program.BeginPass(si + " turning", spindle, {si});
    const double h_start = section_top + doc + cl, h_end = z_b;
    TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState s0, At(nose(s.radius_mm + rn, h_start), a, 0));
    TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState s1, At(nose(s.radius_mm + rn, h_end), a, 0));
    TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState s_out, At(nose(rho_start, h_start), a, 0));
    program.Rapid(s_out);
    program.Rapid(s0);
    program.TurnLinear(s1, f, s.radius_mm, s.radius_mm, true);
    TurnedCut scut = bcut;
    scut.ref = {program.current_operation(), program.current_pass_index(), program.last_move_index()};
    scut.radial_feed = false;
    scut.coord_start_mm = h_start;
    scut.coord_end_mm = h_end;
    TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState s_away, At(nose(s.radius_mm + rn + doc + cl, h_end), a, 0));
    program.Rapid(s_away);
    RetractToSafe();

    NominalFeature side;
    side.name = si;
    side.type = SurfaceType::kCylinder;
    side.radius_mm = s.radius_mm;
    side.h_min_mm = s.shoulder_z_mm;
    side.h_max_mm = section_top;
    side.design_levels_mm = {s.probe_z_mm};
    side.level_min_mm = s.shoulder_z_mm + rn + 0.3;
    side.level_max_mm = section_top - 0.3;
    side.description = "turned side face, " + std::string(setup.where);
    AddFeature(side, scut);

    NominalFeature bottom;
    bottom.name = bi;
    bottom.type = SurfaceType::kPlane;
    bottom.origin_mm = Eigen::Vector3d(0, 0, s.shoulder_z_mm);
    bottom.r_min_mm = s.radius_mm;
    bottom.r_max_mm = r_out;
    bottom.design_levels_mm = {s.radius_mm + p.bottom_probe_fraction * (r_out - s.radius_mm)};
    bottom.level_min_mm = s.radius_mm + rn + 0.3;
    bottom.level_max_mm = r_out - 0.3;
    bottom.description = "turned bottom face, " + std::string(setup.where);
    AddFeature(bottom, bcut);
    return Status::Ok();
  }
};

}  // namespace

Result<TestPiece> BuildTurningPiece(const PieceConfig& config, const kinematics::MachineModel& machine) {
  const auto& p = std::get<TurningPieceParams>(config.params);
  if (machine.type != kinematics::MachineType::kAcTable) {
    return Status(StatusCode::kInvalidArgument, "the seed 002 turning piece needs an A/C swiveling-table machine "
                                                "(ac_table), not " + std::string(kinematics::MachineTypeName(machine.type)));
  }
  TurningBuild b(p, config, machine);
  b.piece.config = config;
  b.piece.name = p.name;
  b.piece.machine = machine;
  b.piece.part_from_datum = Rigid3::Identity();
  b.piece.part_from_datum.translation() = Eigen::Vector3d(0, 0, p.groove_bottom_z_mm);
  // Machine Z above the part in both setups (A = 0: the top face; A = -90: the flange radius).
  b.z_safe_mm = std::max(p.top_z_mm(), p.base_radius_mm) + p.safe_clearance_mm;
  {
    kinematics::AxisState home;
    home.z_mm = b.z_safe_mm;
    b.program.SetStartState(home);
  }
  TPCAL_RETURN_IF_ERROR(b.Groove().WithContext("operation 1 (groove)"));
  TPCAL_RETURN_IF_ERROR(b.Holes().WithContext("operation 2 (holes)"));
  // Paper order: S1/B1, S4/B4, S2/B2, S5/B5, S3/B3, S6/B6.
  for (int i : {0, 3, 1, 4, 2, 5}) {
    TPCAL_RETURN_IF_ERROR(b.TurnStep(i).WithContext("turning step " + std::to_string(i + 1)));
  }
  b.piece.operations = b.program.Finish();
  // Feature order: S_R, B_R, [S_RI], H1..Hn, S1, B1, ..., S6, B6 (the program follows the
  // paper's machining order; the feature list reads by step).
  std::vector<std::string> order = {"S_R", "B_R", "S_RI"};
  for (int k = 0; k < p.hole_count; ++k) order.push_back("H" + std::to_string(k + 1));
  for (int i = 0; i < 6; ++i) {
    order.push_back("S" + std::to_string(i + 1));
    order.push_back("B" + std::to_string(i + 1));
  }
  std::vector<NominalFeature> features;
  std::vector<FeatureCut> cuts;
  for (const std::string& name : order) {
    for (std::size_t k = 0; k < b.piece.features.size(); ++k) {
      if (b.piece.features[k].name == name) {
        features.push_back(b.piece.features[k]);
        cuts.push_back(b.piece.cuts[k]);
      }
    }
  }
  b.piece.features = std::move(features);
  b.piece.cuts = std::move(cuts);
  return std::move(b.piece);
}

}  // namespace internal
}  // namespace tpcal::testpieces
