#include "testpieces/inspection_plan.h"

#include <cmath>
#include <map>

#include "core/units.h"

namespace tpcal::testpieces {
namespace {

using gdt::CharacteristicSpec;
using gdt::CharacteristicType;
using gdt::FeatureKind;
using gdt::FeatureSpec;

FeatureSpec Feature(const std::string& name, FeatureKind kind, gdt::Projection proj = gdt::Projection::kNone) {
  FeatureSpec f;
  f.name = name;
  f.kind = kind;
  f.projection = proj;
  return f;
}

FeatureSpec PlaneUp(const std::string& name) {
  FeatureSpec f = Feature(name, FeatureKind::kPlane);
  f.nominal_direction = Eigen::Vector3d::UnitZ();
  return f;
}

CharacteristicSpec Char(const std::string& name, CharacteristicType type, const std::string& feature,
                        const std::string& datum, const std::string& symbol, const std::string& description) {
  CharacteristicSpec c;
  c.name = name;
  c.type = type;
  c.feature = feature;
  c.datum = datum;
  c.symbol = symbol;
  c.description = description;
  return c;
}

gdt::InspectionPlan TurningPlan(const TestPiece& piece) {
  const auto& p = std::get<TurningPieceParams>(piece.config.params);
  gdt::InspectionPlan plan;
  plan.source = "<test piece: " + piece.name + ">";
  plan.name = piece.name;
  gdt::DatumFrameSpec frame;
  frame.type = gdt::DatumFrameType::kTurning;
  frame.primary = "B_R";
  frame.center = "S_R";
  frame.x_toward = "H1";
  // +Z away from the body below B_R (as samples/plans/turning.yaml): needs no point normals.
  frame.z_sense.rule = gdt::AxisSense::Rule::kAwayFrom;
  frame.z_sense.feature = "S4";
  plan.datum_frame = frame;

  // Nominals for the machine-error equations (seed 002 eqs. 10-27, SEED002_EQUATIONS.md):
  // heights from the A axis, radii from the C axis.
  auto nominal = [&](const std::string& name, double value) { plan.nominals.push_back({name, value, 0}); };
  nominal("z_R_mm", p.groove_bottom_z_mm);
  nominal("z_SR_cut_mm", p.groove_bottom_z_mm + p.groove_wall_lift_mm);
  nominal("r_SR_mm", p.groove_outer_radius_mm);
  nominal("z_h_mm", p.hole_probe_z_mm());
  for (int i = 0; i < 6; ++i) {
    const std::string k = std::to_string(i + 1);
    const TurnedStep& s = p.steps[i];
    nominal("z" + k + "_mm", s.probe_z_mm);
    nominal("z_B" + k + "_mm", s.shoulder_z_mm);
    nominal("r" + k + "_mm", s.radius_mm);
    nominal("rho_B" + k + "_mm", s.radius_mm + p.bottom_probe_fraction * (p.BottomOuterRadius(i) - s.radius_mm));
  }
  nominal("hole_pitch_radius_mm", p.hole_pitch_radius_mm);
  nominal("hole_count", p.hole_count);
  nominal("hole_pitch_deg", 360.0 / p.hole_count);

  plan.features.push_back(PlaneUp("B_R"));
  plan.features.push_back(Feature("S_R", FeatureKind::kCircle, gdt::Projection::kDatumXY));
  if (p.groove_inner_wall_pass) plan.features.push_back(Feature("S_RI", FeatureKind::kCircle, gdt::Projection::kDatumXY));
  FeatureSpec pitch = Feature("C_h", FeatureKind::kPitchCircle, gdt::Projection::kDatumXY);
  for (int k = 0; k < p.hole_count; ++k) {
    const std::string h = "H" + std::to_string(k + 1);
    plan.features.push_back(Feature(h, FeatureKind::kCircle, gdt::Projection::kDatumXY));
    pitch.members.push_back(h);
  }
  plan.features.push_back(pitch);
  for (int i = 1; i <= 6; ++i) {
    plan.features.push_back(Feature("S" + std::to_string(i), FeatureKind::kCircle, gdt::Projection::kDatumXY));
    plan.features.push_back(PlaneUp("B" + std::to_string(i)));
  }

  // Names of the Table 1 items follow samples/plans/turning.yaml (the gdt layer's plan).
  auto& ch = plan.characteristics;
  ch.push_back(Char("t1_concentricity_Ch_SR", CharacteristicType::kConcentricity, "C_h", "S_R",
                    "dx_{Ch,SR}, dy_{Ch,SR}", "seed 002 Table 1 #1: pitch circle of the holes to S_R (eq. 10, 11)"));
  ch.push_back(Char("t2_parallelism_B1_BR", CharacteristicType::kParallelism, "B1", "B_R", "da_{B1,BR}, db_{B1,BR}",
                    "seed 002 Table 1 #2: parallelism of B1 to B_R (eq. 12, 13)"));
  {
    CharacteristicSpec c = Char("t3_distance_B3_BR", CharacteristicType::kPlaneDistance, "B3", "B_R", "dd_{B3,BR}",
                                "seed 002 Table 1 #3: error in distance between B3 and B_R (eq. 14)");
    c.nominal_distance_mm = p.steps[2].shoulder_z_mm - p.groove_bottom_z_mm;
    ch.push_back(c);
  }
  {
    CharacteristicSpec c = Char("t4_size_S3", CharacteristicType::kSize, "S3", "", "dr_{S3}",
                                "seed 002 Table 1 #4: error in radius of S3 (eq. 15)");
    c.nominal_radius_mm = p.steps[2].radius_mm;
    ch.push_back(c);
  }
  ch.push_back(Char("t5_concentricity_S4_SR", CharacteristicType::kConcentricity, "S4", "S_R", "dx_{S4,SR}, dy_{S4,SR}",
                    "seed 002 Table 1 #5: concentricity of S4 to S_R (eq. 16, 17)"));
  ch.push_back(Char("t6_concentricity_S4_S1", CharacteristicType::kConcentricity, "S4", "S1", "dx_{S4,S1}, dy_{S4,S1}",
                    "seed 002 Table 1 #6: concentricity of S4 to S1 (eq. 18, 19)"));
  ch.push_back(Char("t7_concentricity_S6_S3", CharacteristicType::kConcentricity, "S6", "S3", "dx_{S6,S3}, dy_{S6,S3}",
                    "seed 002 Table 1 #7: concentricity of S6 to S3 (eq. 20, 21)"));
  const std::map<int, std::string> circ_names = {{1, "ta_circularity_S1"}, {3, "tb_circularity_S3"},
                                                 {4, "tc_circularity_S4"}, {6, "td_circularity_S6"},
                                                 {2, "circularity_S2"},    {5, "circularity_S5"}};
  const std::map<int, std::string> circ_eq = {{1, "22"}, {2, "23"}, {3, "26"}, {4, "24"}, {5, "25"}, {6, "27"}};
  for (int i = 1; i <= 6; ++i) {
    const std::string si = "S" + std::to_string(i);
    CharacteristicSpec c = Char(circ_names.at(i), CharacteristicType::kCircularity, si, "", "dr_{" + si + "}(C)",
                                "circularity profile of " + si + " (seed 002 eq. " + circ_eq.at(i) + ")");
    c.criterion = gdt::FormCriterion::kLeastSquares;
    ch.push_back(c);
  }
  {
    CharacteristicSpec c = Char("hole_pattern_Ch", CharacteristicType::kHolePattern, "C_h", "", "",
                                "pitch circle of the holes: radius and angular position of each hole (C indexing)");
    c.nominal_radius_mm = p.hole_pitch_radius_mm;
    c.first_angle_deg = 0.0;
    c.pitch_deg = 360.0 / p.hole_count;
    ch.push_back(c);
  }
  // Beyond Table 1, for identification and diagnosis: every turned face's size, centre, and
  // every bottom face's tilt and height.
  for (int i = 1; i <= 6; ++i) {
    const std::string si = "S" + std::to_string(i), bi = "B" + std::to_string(i);
    const TurnedStep& s = p.steps[i - 1];
    if (i != 3) {
      CharacteristicSpec c = Char("size_" + si, CharacteristicType::kSize, si, "", "dr_{" + si + "}",
                                  "radius error of " + si);
      c.nominal_radius_mm = s.radius_mm;
      ch.push_back(c);
    }
    if (i != 4) {
      ch.push_back(Char("concentricity_" + si + "_SR", CharacteristicType::kConcentricity, si, "S_R",
                        "dx_{" + si + ",SR}, dy_{" + si + ",SR}", "centre of " + si + " to S_R"));
    }
    if (i != 1) {
      ch.push_back(Char("parallelism_" + bi + "_BR", CharacteristicType::kParallelism, bi, "B_R",
                        "da_{" + bi + ",BR}, db_{" + bi + ",BR}", "tilt of " + bi + " to B_R"));
    }
    if (i != 3) {
      CharacteristicSpec c = Char("distance_" + bi + "_BR", CharacteristicType::kPlaneDistance, bi, "B_R",
                                  "dd_{" + bi + ",BR}", "height error of " + bi + " from B_R");
      c.nominal_distance_mm = s.shoulder_z_mm - p.groove_bottom_z_mm;
      ch.push_back(c);
    }
  }
  {
    CharacteristicSpec c = Char("size_S_R", CharacteristicType::kSize, "S_R", "", "", "radius error of the groove wall");
    c.nominal_radius_mm = p.groove_outer_radius_mm;
    ch.push_back(c);
    ch.push_back(Char("circularity_S_R", CharacteristicType::kCircularity, "S_R", "", "", "circularity of the groove wall"));
    ch.push_back(Char("flatness_B_R", CharacteristicType::kFlatness, "B_R", "", "", "flatness of the groove bottom"));
  }
  if (p.groove_inner_wall_pass) {
    CharacteristicSpec c = Char("size_S_RI", CharacteristicType::kSize, "S_RI", "", "", "radius error of the inner wall");
    c.nominal_radius_mm = p.groove_inner_radius_mm;
    ch.push_back(c);
    ch.push_back(Char("concentricity_SRI_SR", CharacteristicType::kConcentricity, "S_RI", "S_R", "",
                      "centre of the CW-cut inner wall to the CCW-cut S_R (circular interpolation direction)"));
    ch.push_back(Char("circularity_S_RI", CharacteristicType::kCircularity, "S_RI", "", "",
                      "circularity of the inner wall"));
  }
  return plan;
}

}  // namespace

// Defined with the ISO pieces (iso10791_pieces.cc).
namespace internal {
gdt::InspectionPlan ContourPlan(const TestPiece& piece);
gdt::InspectionPlan FaceMillingPlan(const TestPiece& piece);
gdt::InspectionPlan ConeFrustumPlan(const TestPiece& piece);
}  // namespace internal

Result<gdt::InspectionPlan> BuildInspectionPlan(const TestPiece& piece) {
  gdt::InspectionPlan plan;
  switch (piece.kind()) {
    case PieceKind::kTurning: plan = TurningPlan(piece); break;
    case PieceKind::kContourM1: plan = internal::ContourPlan(piece); break;
    case PieceKind::kFaceMillingM2: plan = internal::FaceMillingPlan(piece); break;
    case PieceKind::kConeFrustum: plan = internal::ConeFrustumPlan(piece); break;
  }
  TPCAL_RETURN_IF_ERROR(gdt::ValidatePlan(plan).WithContext("inspection plan of " + piece.name));
  return plan;
}

}  // namespace tpcal::testpieces
