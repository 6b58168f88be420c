// ISO 10791-7 M2 face-milling piece (iso10791_pieces.h): parameters, builder, inspection plan.
#include <cmath>
#include <sstream>

#include "core/units.h"
#include "testpieces/internal/planning.h"

namespace tpcal::testpieces {
namespace {

Status BadM2(const std::string& key, double value, const std::string& why) {
  std::ostringstream os;
  os << "iso10791_m2." << key << " = " << value << ": " << why;
  return {StatusCode::kInvalidArgument, os.str()};
}

}  // namespace

double FaceMillingPieceParams::width_mm() const {
  const double d = face_mill_diameter_mm;
  return passes * d - (passes - 1) * overlap_fraction * d - 2.0 * edge_clearance_mm;
}

double FaceMillingPieceParams::PassCenterY(int k) const {
  const double d = face_mill_diameter_mm;
  const double covered = passes * d - (passes - 1) * overlap_fraction * d;
  return -0.5 * covered + 0.5 * d + k * (1.0 - overlap_fraction) * d;
}

Status FaceMillingPieceParams::Validate() const {
  struct Named { const char* key; double value; };
  for (const Named& n : {Named{"face_mill_diameter_mm", face_mill_diameter_mm}, Named{"length_mm", length_mm},
                         Named{"height_mm", height_mm}, Named{"cutting_speed_m_per_min", cutting_speed_m_per_min},
                         Named{"feed_per_tooth_mm", feed_per_tooth_mm}, Named{"safe_clearance_mm", safe_clearance_mm}}) {
    if (!(std::isfinite(n.value) && n.value > 0)) return BadM2(n.key, n.value, "must be a positive number");
  }
  if (face_mill_teeth < 1) return BadM2("face_mill_teeth", face_mill_teeth, "must be >= 1");
  if (passes < 1) return BadM2("passes", passes, "must be >= 1");
  if (!(overlap_fraction >= 0.05 && overlap_fraction <= 0.5)) {
    return BadM2("overlap_fraction", overlap_fraction, "must be in [0.05, 0.5] of the cutter diameter");
  }
  if (!(edge_clearance_mm >= 0 && edge_clearance_mm < 0.25 * face_mill_diameter_mm)) {
    return BadM2("edge_clearance_mm", edge_clearance_mm, "must be in [0, D/4)");
  }
  if (!(run_out_mm >= 0)) return BadM2("run_out_mm", run_out_mm, "must be >= 0");
  if (!(width_mm() > 10.0)) return BadM2("passes", passes, "block narrower than 10 mm");
  return Status::Ok();
}

namespace internal {

Result<TestPiece> BuildFaceMillingPiece(const PieceConfig& config, const kinematics::MachineModel& machine) {
  const auto& p = std::get<FaceMillingPieceParams>(config.params);
  TestPiece piece;
  piece.config = config;
  piece.name = p.name;
  piece.machine = machine;
  ProgramBuilder program(config.process);
  const double z = p.height_mm, r = 0.5 * p.face_mill_diameter_mm;
  const double z_safe = z + p.safe_clearance_mm;
  {
    kinematics::AxisState home;
    home.z_mm = z_safe;
    program.SetStartState(home);
  }
  Tool tool;
  tool.number = 1;
  tool.kind = ToolKind::kFaceMill;
  tool.diameter_mm = p.face_mill_diameter_mm;
  tool.teeth = p.face_mill_teeth;
  tool.flute_length_mm = 5.0;
  tool.material = "carbide inserts";
  tool.name = "face mill d" + std::to_string(p.face_mill_diameter_mm);
  Spindle spindle;
  spindle.mode = SpindleMode::kMilling;
  spindle.speed_rpm = p.cutting_speed_m_per_min * 1000.0 / (kPi * p.face_mill_diameter_mm);
  const double feed = p.feed_per_tooth_mm * p.face_mill_teeth * spindle.speed_rpm;
  program.BeginOperation("face milling", "ISO 10791-7 M2: top face in parallel passes along +X, overlap " +
                                             std::to_string(p.overlap_fraction) + " D", tool);
  std::vector<std::string> names;
  for (int k = 0; k < p.passes; ++k) names.push_back("FACE_P" + std::to_string(k + 1));
  std::vector<PathElement> elements;
  const double x0 = -0.5 * p.length_mm - r - p.run_out_mm, x1 = 0.5 * p.length_mm + r + p.run_out_mm;
  for (int k = 0; k < p.passes; ++k) {
    program.BeginPass("pass " + std::to_string(k + 1), spindle, {names[k]});
    const double y = p.PassCenterY(k);
    TPCAL_ASSIGN_OR_RETURN(kinematics::AxisState above, AxesForRefPoint(machine, {x0, y, z_safe}, {}, true));
    TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState start, AxesForRefPoint(machine, {x0, y, z}, {}, true));
    TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState end, AxesForRefPoint(machine, {x1, y, z}, {}, true));
    kinematics::AxisState up = program.state();
    up.z_mm = z_safe;
    program.Rapid(up);
    program.Rapid(above);
    program.Rapid(start);
    program.Linear(end, feed, true);
    PathElement e;
    e.ref = {program.current_operation(), program.current_pass_index(), program.last_move_index()};
    e.start_tip_mm = Eigen::Vector3d(x0, y, z);
    e.end_tip_mm = Eigen::Vector3d(x1, y, z);
    elements.push_back(e);
  }
  kinematics::AxisState up = program.state();
  up.z_mm = z_safe;
  program.Rapid(up);
  piece.operations = program.Finish();

  PathMillCut cut;
  cut.tool_axis = Eigen::Vector3d::UnitZ();
  cut.tool_radius_mm = r;
  cut.end_face = true;
  cut.elements = elements;
  const double half_w = 0.5 * p.width_mm(), half_l = 0.5 * p.length_mm;
  for (int k = 0; k < p.passes; ++k) {
    // The strip pass k cut last: up to where pass k + 1 begins.
    const double y = p.PassCenterY(k);
    const double lo = std::max(-half_w, y - r);
    const double hi = k + 1 < p.passes ? std::min(half_w, p.PassCenterY(k + 1) - r) : half_w;
    NominalFeature f;
    f.name = names[k];
    f.type = SurfaceType::kPlane;
    f.origin_mm = Eigen::Vector3d(0, 0, z);
    f.polygon_uv_mm = {{-half_l, lo}, {half_l, lo}, {half_l, hi}, {-half_l, hi}};
    f.pattern = ProbePattern::kGrid;
    f.description = "top face, region last cut by face-mill pass " + std::to_string(k + 1);
    piece.features.push_back(f);
    piece.cuts.push_back({f.name, cut});
  }
  // Datum (FaceMillingPlan's `targets` frame): the top face is all there is to probe, so the
  // datum targets are the strips' probed patches: z = 0 on the top face, the origin at the
  // centre of FACE_P1's patch (the centroid of its symmetric probing grid), +Y toward the
  // centre of the last strip's patch (pass order). One pass leaves X, Y and the rotation about
  // Z unfixed: then the datum stays the piece frame on the top face and the plan has no frame.
  piece.part_from_datum = Rigid3::Identity();
  const double y_p1 = p.passes > 1 ? 0.5 * (std::max(-half_w, p.PassCenterY(0) - r) +
                                            std::min(half_w, p.PassCenterY(1) - r))
                                   : 0.0;
  piece.part_from_datum.translation() = Eigen::Vector3d(0, y_p1, z);
  return piece;
}

gdt::InspectionPlan FaceMillingPlan(const TestPiece& piece) {
  const auto& p = std::get<FaceMillingPieceParams>(piece.config.params);
  gdt::InspectionPlan plan;
  plan.source = "<test piece: " + piece.name + ">";
  plan.name = piece.name;
  if (p.passes > 1) {
    // The datum targets of BuildFaceMillingPiece's part_from_datum. +Z along the point normals
    // (out of the material): the strips are coplanar, no other feature can orient it.
    gdt::DatumFrameSpec frame;
    frame.type = gdt::DatumFrameType::kTargets;
    frame.primary = "FACE_P1";
    frame.center = "FACE_P1";
    frame.y_toward = "FACE_P" + std::to_string(p.passes);
    frame.z_sense.rule = gdt::AxisSense::Rule::kPointNormals;
    plan.datum_frame = frame;
  }
  for (int k = 0; k < p.passes; ++k) {
    gdt::FeatureSpec f;
    f.name = "FACE_P" + std::to_string(k + 1);
    f.kind = gdt::FeatureKind::kPlane;
    f.nominal_direction = Eigen::Vector3d::UnitZ();
    plan.features.push_back(f);
    gdt::CharacteristicSpec c;
    c.name = "flatness_" + f.name;
    c.type = gdt::CharacteristicType::kFlatness;
    c.feature = f.name;
    c.description = "flatness of the region last cut by pass " + std::to_string(k + 1);
    plan.characteristics.push_back(c);
    if (k > 0) {
      gdt::CharacteristicSpec par;
      par.name = "parallelism_" + f.name + "_FACE_P1";
      par.type = gdt::CharacteristicType::kParallelism;
      par.feature = f.name;
      par.datum = "FACE_P1";
      par.description = "tilt between the strips of pass " + std::to_string(k + 1) + " and pass 1";
      plan.characteristics.push_back(par);
    }
  }
  return plan;
}

}  // namespace internal
}  // namespace tpcal::testpieces
