// Cone frustum (NAS 979 / ISO 10791-7) by simultaneous five-axis flank milling
// (iso10791_pieces.h): parameters, builder, inspection plan.
#include <cmath>
#include <sstream>

#include "core/units.h"
#include "kinematics/inverse_kinematics.h"
#include "testpieces/internal/planning.h"

namespace tpcal::testpieces {
namespace {

Status BadCone(const std::string& key, double value, const std::string& why) {
  std::ostringstream os;
  os << "cone_frustum." << key << " = " << value << ": " << why;
  return {StatusCode::kInvalidArgument, os.str()};
}

constexpr int kSections = 3;  // probing sections (CONE_1 .. CONE_3), bottom to top of the band

}  // namespace

Status ConeFrustumParams::Validate() const {
  struct Named { const char* key; double value; };
  for (const Named& n : {Named{"base_size_mm", base_size_mm}, Named{"base_thickness_mm", base_thickness_mm},
                         Named{"bottom_diameter_mm", bottom_diameter_mm}, Named{"half_angle_deg", half_angle_deg},
                         Named{"height_mm", height_mm}, Named{"end_mill_diameter_mm", end_mill_diameter_mm},
                         Named{"cutting_speed_m_per_min", cutting_speed_m_per_min},
                         Named{"feed_per_tooth_mm", feed_per_tooth_mm}, Named{"tip_clearance_mm", tip_clearance_mm},
                         Named{"safe_clearance_mm", safe_clearance_mm},
                         Named{"probe_band_margin_mm", probe_band_margin_mm}}) {
    if (!(std::isfinite(n.value) && n.value > 0)) return BadCone(n.key, n.value, "must be a positive number");
  }
  if (!(axis_tilt_deg >= 0 && axis_tilt_deg < 45)) return BadCone("axis_tilt_deg", axis_tilt_deg, "must be in [0, 45)");
  if (!(half_angle_deg < 45)) return BadCone("half_angle_deg", half_angle_deg, "must be < 45");
  if (end_mill_teeth < 1) return BadCone("end_mill_teeth", end_mill_teeth, "must be >= 1");
  if (path_steps < 36) return BadCone("path_steps", path_steps, "must be >= 36");
  const double r_top = 0.5 * bottom_diameter_mm - height_mm * std::tan(DegToRad(half_angle_deg));
  if (!(r_top > 1.0)) return BadCone("height_mm", height_mm, "the cone closes below its top");
  if (!(bottom_diameter_mm + 2 * end_mill_diameter_mm < base_size_mm)) {
    return BadCone("base_size_mm", base_size_mm, "the tool must stay over the base plate");
  }
  // An extra cone `offset` from the first (0: none): clear of it with a tool between, on the plate.
  auto check_offset = [&](const char* key, const char* which, double offset) -> Status {
    if (!(std::isfinite(offset) && offset >= 0)) return BadCone(key, offset, "must be 0 (none) or positive");
    if (offset == 0) return Status::Ok();
    if (!(offset > bottom_diameter_mm + 2 * end_mill_diameter_mm))
      return BadCone(key, offset, "the cones and the tool between them must not overlap (> bottom diameter + 2 tool diameters)");
    if (!(2 * (offset + 0.5 * bottom_diameter_mm + end_mill_diameter_mm) < base_size_mm))
      return BadCone("base_size_mm", base_size_mm,
                     std::string("the tool must stay over the base plate around the ") + which +
                         " cone (> 2 (offset + bottom radius + tool diameter))");
    return Status::Ok();
  };
  TPCAL_RETURN_IF_ERROR(check_offset("second_cone.offset_mm", "second", second_cone_offset_mm));
  TPCAL_RETURN_IF_ERROR(check_offset("third_cone.offset_mm", "third", third_cone_offset_mm));
  if (third_cone_offset_mm > 0 && !(second_cone_offset_mm > 0))
    return BadCone("third_cone.offset_mm", third_cone_offset_mm, "needs the second cone (second_cone.offset_mm > 0)");
  return Status::Ok();
}

namespace internal {
namespace {

// The cone feature (before the band limits are known) of the parameters.
NominalFeature ConeSurface(const ConeFrustumParams& p) {
  const double tau = DegToRad(p.axis_tilt_deg);
  NominalFeature f;
  f.type = SurfaceType::kCone;
  f.origin_mm = Eigen::Vector3d(0, 0, p.base_thickness_mm);
  f.axis = Eigen::Vector3d(std::sin(tau), 0, std::cos(tau));
  f.ref_dir = Eigen::Vector3d(std::cos(tau), 0, -std::sin(tau));
  f.radius_mm = 0.5 * p.bottom_diameter_mm;
  f.half_angle_rad = DegToRad(p.half_angle_deg);
  return f;
}

// Lowest cone height of the tool tip such that the tool's end disc stays tip_clearance above the
// base top at every azimuth (sampled every 0.1 deg; the condition is linear in h).
double TipHeight(const ConeFrustumParams& p, const NominalFeature& cone) {
  const double rt = 0.5 * p.end_mill_diameter_mm;
  const double a = cone.half_angle_rad;
  double h_req = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3600; ++k) {
    const double th = 2 * kPi * k / 3600;
    const Eigen::Vector3d er = std::cos(th) * cone.ref_dir + std::sin(th) * cone.v_dir();
    const Eigen::Vector3d g = std::cos(a) * cone.axis - std::sin(a) * er;
    const double disc_drop = rt * std::sqrt(std::max(0.0, 1.0 - g.z() * g.z()));
    auto low = [&](double h) {
      const SurfaceCoords c{th, h};
      return (PointAt(cone, c) + rt * NormalAt(cone, c)).z() - disc_drop;
    };
    const double z0 = low(0.0), slope = low(1.0) - z0;
    h_req = std::max(h_req, (p.base_thickness_mm + p.tip_clearance_mm - z0) / slope);
  }
  return std::max(h_req, 0.0);
}

}  // namespace

Result<TestPiece> BuildConeFrustumPiece(const PieceConfig& config, const kinematics::MachineModel& machine) {
  const auto& p = std::get<ConeFrustumParams>(config.params);
  if (machine.type == kinematics::MachineType::kXyz) {
    return Status(StatusCode::kInvalidArgument, "the cone frustum needs a five-axis machine (simultaneous flank milling)");
  }
  TestPiece piece;
  piece.config = config;
  piece.name = p.name;
  piece.machine = machine;
  NominalFeature cone = ConeSurface(p);
  const double h_tip = TipHeight(p, cone);
  const double rt = 0.5 * p.end_mill_diameter_mm;
  const double band_lo = h_tip + p.probe_band_margin_mm, band_hi = p.height_mm - p.probe_band_margin_mm;
  if (!(band_hi - band_lo > 3.0 * kSections)) {
    return Status(StatusCode::kInvalidArgument,
                  "cone_frustum: machined band too short to probe (tool tip at cone height " + std::to_string(h_tip) +
                      " mm for height_mm " + std::to_string(p.height_mm) + ")");
  }
  const double flute = (p.height_mm - h_tip) / std::cos(cone.half_angle_rad) + 5.0;

  ProgramBuilder program(config.process);
  const double z_safe = p.base_thickness_mm + p.height_mm + p.safe_clearance_mm;
  {
    kinematics::AxisState home;
    home.z_mm = z_safe;
    program.SetStartState(home);
  }
  Tool tool;
  tool.number = 1;
  tool.kind = ToolKind::kEndMill;
  tool.diameter_mm = p.end_mill_diameter_mm;
  tool.teeth = p.end_mill_teeth;
  tool.flute_length_mm = flute;
  tool.material = "carbide";
  tool.name = "flat end mill d" + std::to_string(p.end_mill_diameter_mm);
  Spindle spindle;
  spindle.mode = SpindleMode::kMilling;
  spindle.speed_rpm = p.cutting_speed_m_per_min * 1000.0 / (kPi * p.end_mill_diameter_mm);
  const double feed = p.feed_per_tooth_mm * p.end_mill_teeth * spindle.speed_rpm;
  // One simultaneous five-axis flank pass around `cone` (its own operation), sections named
  // `prefix`1 .. `prefix`k.
  auto cut_cone = [&](const NominalFeature& cone, const std::string& prefix, const std::string& op_name) -> Status {
    std::vector<std::string> section_names;
    for (int s = 0; s < kSections; ++s) section_names.push_back(prefix + std::to_string(s + 1));
    program.BeginOperation(op_name, "NAS 979 / ISO 10791-7 cone frustum: one simultaneous five-axis flank pass, "
                                    "tool axis along the generatrix, climb (CW about the cone axis)", tool);
    program.BeginPass("flank", spindle, section_names);
    // Poses every 2 pi / steps, CW (climb around an island), from theta = 0.
    FlankMillCut cut;
    cut.steps = p.path_steps;
    cut.theta_start_rad = 0.0;
    cut.counter_clockwise = false;
    cut.tool_radius_mm = rt;
    cut.h_tip_mm = h_tip;
    cut.negative_tilt = true;
    const double h_mid = 0.5 * (h_tip + p.height_mm);
    std::vector<kinematics::AxisState> poses;
    kinematics::AxisState previous;
    for (int k = 0; k <= p.path_steps; ++k) {
      const double th = -2 * kPi * k / p.path_steps;
      const double alpha = cone.half_angle_rad;
      const Eigen::Vector3d er = std::cos(th) * cone.ref_dir + std::sin(th) * cone.v_dir();
      const Eigen::Vector3d g = std::cos(alpha) * cone.axis - std::sin(alpha) * er;
      const SurfaceCoords at_tip{th, h_tip};
      const Eigen::Vector3d tip = PointAt(cone, at_tip) + rt * NormalAt(cone, at_tip);
      TPCAL_ASSIGN_OR_RETURN(const std::vector<kinematics::AxisState> sols,
                             kinematics::RotaryAnglesForToolAxis(machine, g, k == 0 ? 0.0 : previous.c_rad));
      const kinematics::AxisState* chosen = nullptr;
      for (const auto& s : sols) {
        if (s.a_rad + s.b_rad <= 0) chosen = &s;
      }
      if (!chosen) return Status(StatusCode::kInvalidArgument, "cone_frustum: no rotary solution with A (B) <= 0");
      kinematics::AxisState rot = *chosen;
      if (k > 0) rot.c_rad = previous.c_rad + std::remainder(rot.c_rad - previous.c_rad, 2 * kPi);
      TPCAL_ASSIGN_OR_RETURN(kinematics::AxisState axes, AxesForRefPoint(machine, tip, rot, true));
      previous = axes;
      poses.push_back(axes);
    }
    // Approach: above the start pose, then down along the tool axis, then the pass.
    {
      kinematics::AxisState above = poses.front();
      above.z_mm = z_safe;
      kinematics::AxisState up = program.state();
      up.z_mm = z_safe;
      program.Rapid(up);
      program.Rapid(above);
      program.Linear(poses.front(), 0.5 * feed, false);
    }
    for (int k = 1; k <= p.path_steps; ++k) {
      // Feed of the contact point at the middle of the band.
      const double th0 = -2 * kPi * (k - 1) / p.path_steps, th1 = -2 * kPi * k / p.path_steps;
      const double length = (PointAt(cone, {th1, h_mid}) - PointAt(cone, {th0, h_mid})).norm();
      program.Linear(poses[k], feed, true, length);
      if (k == 1) cut.ref = {program.current_operation(), program.current_pass_index(), program.last_move_index()};
    }
    {
      kinematics::AxisState up = program.state();
      up.z_mm = z_safe;
      program.Rapid(up);
    }

    // Sections: three bands of the machined flank, each probed on its middle circle.
    const double step = (band_hi - band_lo) / kSections;
    for (int s = 0; s < kSections; ++s) {
      NominalFeature f = cone;
      f.name = section_names[static_cast<std::size_t>(s)];
      f.h_min_mm = band_lo - p.probe_band_margin_mm * (s == 0) + s * step;
      f.h_max_mm = band_lo + (s + 1) * step + p.probe_band_margin_mm * (s == kSections - 1);
      f.design_levels_mm = {band_lo + (s + 0.5) * step};
      f.fixed_levels = true;
      f.level_min_mm = f.h_min_mm;
      f.level_max_mm = f.h_max_mm;
      std::ostringstream os;
      os << "cone flank section " << s + 1
         << (prefix == "CONE_" ? "" : prefix == "CONE2_" ? " of the second cone" : " of the third cone") << " (cone height "
         << f.design_levels_mm[0] << " mm), five-axis flank milling";
      f.description = os.str();
      piece.features.push_back(f);
      piece.cuts.push_back({f.name, cut});
    }
    return Status::Ok();
  };
  TPCAL_RETURN_IF_ERROR(cut_cone(cone, "CONE_", "cone flank"));
  if (p.second_cone_offset_mm > 0) {
    NominalFeature second = cone;
    second.origin_mm.x() += p.second_cone_offset_mm;
    TPCAL_RETURN_IF_ERROR(cut_cone(second, "CONE2_", "second cone flank"));
  }
  if (p.third_cone_offset_mm > 0) {
    NominalFeature third = cone;
    third.origin_mm.y() += p.third_cone_offset_mm;
    TPCAL_RETURN_IF_ERROR(cut_cone(third, "CONE3_", "third cone flank"));
  }
  piece.operations = program.Finish();

  // Datum (ConeFrustumPlan's `targets` frame): +Z along the axis of the CONE_1 section toward
  // CONE_3, origin at its centre, +X toward its first probed point (azimuth 0, along ref_dir):
  // a cone of revolution does not fix the azimuth, the probing order does.
  {
    const NominalFeature& c1 = piece.features.front();
    Eigen::Matrix3d r;
    r.col(0) = c1.ref_dir;
    r.col(1) = c1.v_dir();
    r.col(2) = c1.axis;
    piece.part_from_datum = MakeRigid(r, c1.origin_mm + c1.design_levels_mm[0] * c1.axis);
  }
  return piece;
}

gdt::InspectionPlan ConeFrustumPlan(const TestPiece& piece) {
  gdt::InspectionPlan plan;
  plan.source = "<test piece: " + piece.name + ">";
  plan.name = piece.name;
  {
    // The datum of BuildConeFrustumPiece's part_from_datum.
    gdt::DatumFrameSpec frame;
    frame.type = gdt::DatumFrameType::kTargets;
    frame.primary = piece.features.front().name;
    frame.center = frame.primary;
    frame.x_toward = frame.primary;
    frame.toward_first_point = true;
    frame.z_sense.rule = gdt::AxisSense::Rule::kToward;
    frame.z_sense.feature = piece.features.back().name;
    plan.datum_frame = frame;
  }
  for (const NominalFeature& nf : piece.features) {
    gdt::FeatureSpec f;
    f.name = nf.name;
    f.kind = gdt::FeatureKind::kCircle;
    f.projection = gdt::Projection::kNone;
    plan.features.push_back(f);
    gdt::CharacteristicSpec c;
    c.name = "circularity_" + nf.name;
    c.type = gdt::CharacteristicType::kCircularity;
    c.feature = nf.name;
    c.criterion = gdt::FormCriterion::kLeastSquares;
    c.description = "circularity of the cone section (NAS 979 / ISO 10791-7)";
    plan.characteristics.push_back(c);
    gdt::CharacteristicSpec size;
    size.name = "size_" + nf.name;
    size.type = gdt::CharacteristicType::kSize;
    size.feature = nf.name;
    size.nominal_radius_mm = nf.radius_mm - nf.design_levels_mm[0] * std::tan(nf.half_angle_rad);
    size.description = "radius of the cone section";
    plan.characteristics.push_back(size);
  }
  return plan;
}

}  // namespace internal
}  // namespace tpcal::testpieces
