// ISO 10791-7 M1 contouring piece (iso10791_pieces.h): parameters, builder, inspection plan.
#include <cmath>
#include <sstream>

#include "core/units.h"
#include "testpieces/internal/planning.h"

namespace tpcal::testpieces {
namespace {

Status BadM1(const std::string& key, double value, const std::string& why) {
  std::ostringstream os;
  os << "iso10791_m1." << key << " = " << value << ": " << why;
  return {StatusCode::kInvalidArgument, os.str()};
}

double Cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// Largest distance from the origin of a polygon's vertices, and smallest distance of its edges.
double MaxVertexRadius(const std::vector<Eigen::Vector2d>& poly) {
  double r = 0;
  for (const auto& v : poly) r = std::max(r, v.norm());
  return r;
}
double MinEdgeDistance(const std::vector<Eigen::Vector2d>& poly) {
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Eigen::Vector2d a = poly[i], b = poly[(i + 1) % poly.size()];
    d = std::min(d, std::abs(Cross2((b - a).normalized(), -a)));
  }
  return d;
}

}  // namespace

// Layer outlines in the XY plane, CCW (part frame, mm).
namespace internal {
std::vector<Eigen::Vector2d> SquareOutline(double side) {
  const double h = 0.5 * side;
  return {{-h, -h}, {h, -h}, {h, h}, {-h, h}};
}
std::vector<Eigen::Vector2d> DiamondOutline(double side) {
  const double r = side / std::sqrt(2.0);
  return {{0, -r}, {r, 0}, {0, r}, {-r, 0}};
}
// Slope quadrilateral: SL3 (bottom, 3 deg), SLX_P (right), SL6 (top, 6 deg), SLX_N (left).
std::vector<Eigen::Vector2d> SlopeOutline(const ContourPieceParams& p) {
  const double t3 = std::tan(DegToRad(p.slope_small_angle_deg));
  const double t6 = std::tan(DegToRad(p.slope_large_angle_deg));
  const double x = p.slope_half_length_mm, o = p.slope_offset_mm;
  return {{-x, -o - x * t3}, {x, -o + x * t3}, {x, o - x * t6}, {-x, o + x * t6}};
}
}  // namespace internal

ContourPieceParams ContourPieceParams::ForSize(double size_mm) {
  ContourPieceParams p;
  const double s = size_mm / 320.0;
  p.size_mm = size_mm;
  std::ostringstream os;
  os << "ISO 10791-7 M1 (" << size_mm << ")";
  p.name = os.str();
  for (double* v : {&p.base_thickness_mm, &p.square_side_mm, &p.square_height_mm, &p.diamond_side_mm,
                    &p.diamond_height_mm, &p.circle_diameter_mm, &p.circle_height_mm, &p.slope_half_length_mm,
                    &p.slope_offset_mm, &p.slope_height_mm, &p.bore_diameter_mm, &p.end_mill_diameter_mm}) {
    *v *= s;
  }
  return p;
}

Status ContourPieceParams::Validate() const {
  struct Named { const char* key; double value; };
  for (const Named& n : {Named{"size_mm", size_mm}, Named{"base_thickness_mm", base_thickness_mm},
                         Named{"square_side_mm", square_side_mm}, Named{"square_height_mm", square_height_mm},
                         Named{"diamond_side_mm", diamond_side_mm}, Named{"diamond_height_mm", diamond_height_mm},
                         Named{"circle_diameter_mm", circle_diameter_mm}, Named{"circle_height_mm", circle_height_mm},
                         Named{"slope_half_length_mm", slope_half_length_mm}, Named{"slope_offset_mm", slope_offset_mm},
                         Named{"slope_small_angle_deg", slope_small_angle_deg},
                         Named{"slope_large_angle_deg", slope_large_angle_deg}, Named{"slope_height_mm", slope_height_mm},
                         Named{"bore_diameter_mm", bore_diameter_mm}, Named{"end_mill_diameter_mm", end_mill_diameter_mm},
                         Named{"cutting_speed_m_per_min", cutting_speed_m_per_min},
                         Named{"feed_per_tooth_mm", feed_per_tooth_mm}, Named{"safe_clearance_mm", safe_clearance_mm}}) {
    if (!(std::isfinite(n.value) && n.value > 0)) return BadM1(n.key, n.value, "must be a positive number");
  }
  if (end_mill_teeth < 1) return BadM1("end_mill_teeth", end_mill_teeth, "must be >= 1");
  if (!(probe_height_fraction > 0 && probe_height_fraction < 1)) {
    return BadM1("probe_height_fraction", probe_height_fraction, "must be in (0, 1)");
  }
  const double rt = 0.5 * end_mill_diameter_mm;
  if (!(square_side_mm < size_mm - 2.0)) return BadM1("square_side_mm", square_side_mm, "must fit on the base plate");
  if (!(0.5 * square_side_mm + 2 * rt >= 0.5 * size_mm + 0.5)) {
    return BadM1("end_mill_diameter_mm", end_mill_diameter_mm,
                 "the square contour's tool end must cover the whole FLOOR frame (tool diameter >= (size - square) / 2)");
  }
  if (!(diamond_side_mm / std::sqrt(2.0) < 0.5 * square_side_mm - 1.0)) {
    return BadM1("diamond_side_mm", diamond_side_mm, "diamond corners must lie 1 mm inside the square");
  }
  if (!(0.5 * circle_diameter_mm < 0.5 * diamond_side_mm - 1.0)) {
    return BadM1("circle_diameter_mm", circle_diameter_mm, "circle must lie 1 mm inside the diamond");
  }
  if (!(slope_small_angle_deg < 45 && slope_large_angle_deg < 45)) {
    return BadM1("slope_large_angle_deg", slope_large_angle_deg, "slope angles must be < 45 deg");
  }
  const auto slope = internal::SlopeOutline(*this);
  if (!(MaxVertexRadius(slope) < 0.5 * circle_diameter_mm - 1.0)) {
    return BadM1("slope_half_length_mm", slope_half_length_mm, "slope quadrilateral must lie 1 mm inside the circle");
  }
  if (!(0.5 * bore_diameter_mm < MinEdgeDistance(slope) - 2.0)) {
    return BadM1("bore_diameter_mm", bore_diameter_mm, "bore must lie 2 mm inside the slope quadrilateral");
  }
  if (!(rt < 0.5 * bore_diameter_mm - 0.5)) {
    return BadM1("end_mill_diameter_mm", end_mill_diameter_mm, "the end mill must fit in the bore");
  }
  if (!(2.0 * slope_half_length_mm > 2 * 1.5 + 1.0)) {
    return BadM1("slope_half_length_mm", slope_half_length_mm, "slope faces too short to probe");
  }
  return Status::Ok();
}

namespace internal {
namespace {

struct Layer {
  std::string op_name;
  double z_bottom, z_top;
};

struct ContourBuild {
  const ContourPieceParams& p;
  const kinematics::MachineModel& machine;
  ProgramBuilder program;
  TestPiece piece;
  double z_safe = 0;
  Tool tool;
  Spindle spindle;
  double feed = 0;

  ContourBuild(const ContourPieceParams& params, const PieceConfig& config, const kinematics::MachineModel& m)
      : p(params), machine(m), program(config.process) {}

  Result<kinematics::AxisState> At(const Eigen::Vector3d& ref) {
    return AxesForRefPoint(machine, ref, kinematics::AxisState{}, true);
  }
  Status RapidAbove(const Eigen::Vector3d& ref) {
    kinematics::AxisState s = program.state();
    if (s.z_mm < z_safe) {
      s.z_mm = z_safe;
      program.Rapid(s);
    }
    TPCAL_ASSIGN_OR_RETURN(kinematics::AxisState above, At(Eigen::Vector3d(ref.x(), ref.y(), z_safe)));
    program.Rapid(above);
    return Status::Ok();
  }
  PathElement LastElement(bool arc) {
    PathElement e;
    e.ref = {program.current_operation(), program.current_pass_index(), program.last_move_index()};
    e.arc = arc;
    return e;
  }

  // Climb-milled contour (CW) around the convex island `poly` (CCW vertices) with the tool tip
  // at z. Returns one list of line elements per edge (index of the CCW edge i: v_i -> v_i+1) and
  // the vertex arcs.
  Status Island(const std::vector<Eigen::Vector2d>& poly, double z, std::vector<std::vector<PathElement>>* edges,
                std::vector<PathElement>* arcs) {
    const double R = tool.radius_mm();
    const int n = static_cast<int>(poly.size());
    edges->assign(n, {});
    auto normal = [&](int i) {
      const Eigen::Vector2d e = (poly[(i + 1) % n] - poly[i]).normalized();
      return Eigen::Vector2d(e.y(), -e.x());
    };
    auto P3 = [&](const Eigen::Vector2d& q) { return Eigen::Vector3d(q.x(), q.y(), z); };
    // Start at the middle of edge 0, going CW (toward v_0).
    const Eigen::Vector2d mid0 = 0.5 * (poly[0] + poly[1]) + R * normal(0);
    const Eigen::Vector2d lead = mid0 + 2.0 * normal(0);
    TPCAL_RETURN_IF_ERROR(RapidAbove(P3(lead)));
    TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState down, At(P3(lead)));
    program.Linear(down, 0.5 * feed, false);
    TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState start, At(P3(mid0)));
    program.Linear(start, feed, true);
    Eigen::Vector2d current = mid0;
    // CW order: edge 0 (second half, toward v0), arc at v0, edge n-1 (v_{n-1} side reversed), ...
    for (int step = 0; step <= n; ++step) {
      const int i = (n - step) % n;  // CCW index of the edge being cut
      const Eigen::Vector2d end = step == n ? mid0 : poly[i] + R * normal(i);
      TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState to, At(P3(end)));
      program.Linear(to, feed, true);
      PathElement e = LastElement(false);
      e.start_tip_mm = P3(current);
      e.end_tip_mm = P3(end);
      (*edges)[i].push_back(e);
      current = end;
      if (step == n) break;
      // Arc about v_i from normal(i) to normal(i - 1), CW.
      const int prev = (i + n - 1) % n;
      const double angle = std::acos(std::clamp(normal(i).dot(normal(prev)), -1.0, 1.0));
      TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState centre, At(P3(poly[i])));
      program.Arc(Eigen::Vector2d(centre.x_mm, centre.y_mm), angle, true, feed, true);
      PathElement a = LastElement(true);
      a.center_mm = P3(poly[i]);
      a.start_dir = Eigen::Vector3d(normal(i).x(), normal(i).y(), 0);
      a.radius_mm = R;
      a.angle_rad = angle;
      a.clockwise = true;
      arcs->push_back(a);
      current = poly[i] + R * normal(prev);
    }
    program.Linear(down, feed, false);
    return Status::Ok();
  }

  // Full circle of the tool centre (radius R_path about the part Z axis) at z, starting at +X.
  Result<PathElement> FullCircle(double path_radius, double z, bool ccw, double lead) {
    const Eigen::Vector3d start(path_radius, 0, z), plunge(path_radius + lead, 0, z);
    TPCAL_RETURN_IF_ERROR(RapidAbove(plunge));
    TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState down, At(plunge));
    program.Linear(down, 0.5 * feed, false);
    TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState in, At(start));
    program.Linear(in, feed, true);
    TPCAL_ASSIGN_OR_RETURN(const kinematics::AxisState centre, At(Eigen::Vector3d(0, 0, z)));
    program.Arc(Eigen::Vector2d(centre.x_mm, centre.y_mm), 2 * kPi, !ccw, feed, true);
    PathElement e = LastElement(true);
    e.center_mm = Eigen::Vector3d(0, 0, z);
    e.start_dir = Eigen::Vector3d::UnitX();
    e.radius_mm = path_radius;
    e.angle_rad = 2 * kPi;
    e.clockwise = !ccw;
    program.Linear(down, feed, false);
    return e;
  }

  PathMillCut Cut(bool end_face, std::vector<PathElement> elements) const {
    PathMillCut c;
    c.tool_axis = Eigen::Vector3d::UnitZ();
    c.tool_radius_mm = tool.radius_mm();
    c.corner_radius_mm = 0.0;
    c.end_face = end_face;
    c.elements = std::move(elements);
    return c;
  }

  void AddFeature(NominalFeature f, CutModel cut) {
    piece.cuts.push_back({f.name, std::move(cut)});
    piece.features.push_back(std::move(f));
  }

  // Straight side face on the CCW edge a -> b of a layer [z0, z1]: normal outward.
  void SideFace(const std::string& name, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double z0, double z1,
                const std::vector<PathElement>& elements, const std::string& description) {
    const Eigen::Vector2d e = (b - a).normalized();
    NominalFeature f;
    f.name = name;
    f.type = SurfaceType::kPlane;
    f.axis = Eigen::Vector3d(e.y(), -e.x(), 0);
    f.ref_dir = Eigen::Vector3d::UnitZ().cross(f.axis);  // along the edge, a -> b
    const Eigen::Vector2d mid = 0.5 * (a + b);
    f.origin_mm = Eigen::Vector3d(mid.x(), mid.y(), z0);
    const double half = 0.5 * (b - a).norm();
    f.polygon_uv_mm = {{-half, 0}, {half, 0}, {half, z1 - z0}, {-half, z1 - z0}};
    f.pattern = ProbePattern::kLines;
    f.fixed_levels = true;
    f.design_levels_mm = {p.probe_height_fraction * (z1 - z0)};
    f.level_min_mm = 0.3;
    f.level_max_mm = z1 - z0 - 0.3;
    f.line_u_min_mm = -half;
    f.line_u_max_mm = half;
    f.description = description;
    AddFeature(f, Cut(false, elements));
  }

  Status Build() {
    const double b = p.floor_z_mm();
    const double z_sq = b + p.square_height_mm;
    const double z_di = z_sq + p.diamond_height_mm;
    const double z_ci = z_di + p.circle_height_mm;
    const double z_top = z_ci + p.slope_height_mm;
    z_safe = z_top + p.safe_clearance_mm;
    {
      kinematics::AxisState home;
      home.z_mm = z_safe;
      program.SetStartState(home);
    }
    tool.number = 1;
    tool.kind = ToolKind::kEndMill;
    tool.diameter_mm = p.end_mill_diameter_mm;
    tool.teeth = p.end_mill_teeth;
    tool.flute_length_mm = z_top - b + 5.0;
    tool.material = "carbide";
    tool.name = "flat end mill d" + std::to_string(p.end_mill_diameter_mm);
    spindle.mode = SpindleMode::kMilling;
    spindle.speed_rpm = p.cutting_speed_m_per_min * 1000.0 / (kPi * p.end_mill_diameter_mm);
    feed = p.feed_per_tooth_mm * p.end_mill_teeth * spindle.speed_rpm;

    // 1: square (its tool end also finishes FLOOR, the base top around the square).
    program.BeginOperation("square", "ISO 10791-7 M1: square contour, climb (CW), tool tip on the base top", tool);
    program.BeginPass("square contour", spindle, {"FLOOR", "SQ_XP", "SQ_YP", "SQ_XN", "SQ_YN"});
    const auto sq = SquareOutline(p.square_side_mm);
    std::vector<std::vector<PathElement>> sq_edges;
    std::vector<PathElement> sq_arcs;
    TPCAL_RETURN_IF_ERROR(Island(sq, b, &sq_edges, &sq_arcs));
    // 2: diamond.
    program.BeginOperation("diamond", "ISO 10791-7 M1: diamond (square turned 45 deg) contour, climb", tool);
    program.BeginPass("diamond contour", spindle, {"DI_1", "DI_2", "DI_3", "DI_4"});
    const auto di = DiamondOutline(p.diamond_side_mm);
    std::vector<std::vector<PathElement>> di_edges;
    std::vector<PathElement> di_arcs;
    TPCAL_RETURN_IF_ERROR(Island(di, z_sq, &di_edges, &di_arcs));
    // 3: circle.
    program.BeginOperation("circle", "ISO 10791-7 M1: circle boss by circular interpolation, climb (G2)", tool);
    program.BeginPass("circle contour", spindle, {"CIRCLE"});
    TPCAL_ASSIGN_OR_RETURN(const PathElement circle,
                           FullCircle(0.5 * p.circle_diameter_mm + tool.radius_mm(), z_di, false, 2.0));
    // 4: slope quadrilateral.
    program.BeginOperation("slopes", "ISO 10791-7 M1: small-angle faces (3 and 6 deg to X), climb", tool);
    program.BeginPass("slope contour", spindle, {"SL3", "SLX_P", "SL6", "SLX_N"});
    const auto sl = SlopeOutline(p);
    std::vector<std::vector<PathElement>> sl_edges;
    std::vector<PathElement> sl_arcs;
    TPCAL_RETURN_IF_ERROR(Island(sl, z_ci, &sl_edges, &sl_arcs));
    // 5: bore (circular interpolation at full depth, climb on a bore = CCW).
    program.BeginOperation("bore", "ISO 10791-7 M1: central bore by circular interpolation, climb (G3)", tool);
    program.BeginPass("bore", spindle, {"BORE"});
    TPCAL_ASSIGN_OR_RETURN(const PathElement bore,
                           FullCircle(0.5 * p.bore_diameter_mm - tool.radius_mm(), b, true, -1.0));
    kinematics::AxisState s = program.state();
    s.z_mm = z_safe;
    program.Rapid(s);
    piece.operations = program.Finish();

    // Features.
    NominalFeature floor;
    floor.name = "FLOOR";
    floor.type = SurfaceType::kPlane;
    floor.origin_mm = Eigen::Vector3d(0, 0, b);
    floor.polygon_uv_mm = SquareOutline(p.size_mm);
    floor.hole_uv_mm = sq;
    floor.pattern = ProbePattern::kGrid;
    floor.description = "base top around the square, end of the square-contour tool (primary datum)";
    std::vector<PathElement> all = sq_arcs;
    for (const auto& e : sq_edges) all.insert(all.end(), e.begin(), e.end());
    AddFeature(floor, Cut(true, all));
    const char* sq_names[4] = {"SQ_YN", "SQ_XP", "SQ_YP", "SQ_XN"};
    for (int i = 0; i < 4; ++i) {
      SideFace(sq_names[i], sq[i], sq[(i + 1) % 4], b, z_sq, sq_edges[i], "square side");
    }
    for (int i = 0; i < 4; ++i) {
      SideFace("DI_" + std::to_string(i + 1), di[i], di[(i + 1) % 4], z_sq, z_di, di_edges[i],
               "diamond side (normal at " + std::to_string(45 + 90 * i) + " deg)");
    }
    NominalFeature c;
    c.name = "CIRCLE";
    c.type = SurfaceType::kCylinder;
    c.radius_mm = 0.5 * p.circle_diameter_mm;
    c.h_min_mm = z_di;
    c.h_max_mm = z_ci;
    c.design_levels_mm = {z_di + p.probe_height_fraction * p.circle_height_mm};
    c.level_min_mm = z_di + 0.3;
    c.level_max_mm = z_ci - 0.3;
    c.description = "circle boss, circular interpolation (G2)";
    AddFeature(c, Cut(false, {circle}));
    const char* sl_names[4] = {"SL3", "SLX_P", "SL6", "SLX_N"};
    const char* sl_desc[4] = {"small-angle face, 3 deg to X (-Y side)", "slope layer end (+X)",
                              "small-angle face, 6 deg to X (+Y side)", "slope layer end (-X)"};
    for (int i = 0; i < 4; ++i) SideFace(sl_names[i], sl[i], sl[(i + 1) % 4], z_ci, z_top, sl_edges[i], sl_desc[i]);
    NominalFeature bo;
    bo.name = "BORE";
    bo.type = SurfaceType::kCylinder;
    bo.internal = true;
    bo.radius_mm = 0.5 * p.bore_diameter_mm;
    bo.h_min_mm = b;
    bo.h_max_mm = z_top;
    bo.design_levels_mm = {0.5 * (b + z_top)};
    bo.level_min_mm = b + 0.5;
    bo.level_max_mm = z_top - 0.5;
    bo.description = "central bore, circular interpolation (G3) (tertiary datum)";
    AddFeature(bo, Cut(false, {bore}));

    // Datum (3-2-1): z = 0 on FLOOR, y = 0 on SQ_YN, x = 0 at the bore axis.
    piece.part_from_datum = Rigid3::Identity();
    piece.part_from_datum.translation() = Eigen::Vector3d(0, -0.5 * p.square_side_mm, b);
    return Status::Ok();
  }
};

}  // namespace

Result<TestPiece> BuildContourPiece(const PieceConfig& config, const kinematics::MachineModel& machine) {
  const auto& p = std::get<ContourPieceParams>(config.params);
  ContourBuild b(p, config, machine);
  b.piece.config = config;
  b.piece.name = p.name;
  b.piece.machine = machine;
  TPCAL_RETURN_IF_ERROR(b.Build());
  return std::move(b.piece);
}

gdt::InspectionPlan ContourPlan(const TestPiece& piece) {
  const auto& p = std::get<ContourPieceParams>(piece.config.params);
  using gdt::CharacteristicType;
  using gdt::FeatureKind;
  gdt::InspectionPlan plan;
  plan.source = "<test piece: " + piece.name + ">";
  plan.name = piece.name;
  gdt::DatumFrameSpec frame;
  frame.type = gdt::DatumFrameType::kThreeTwoOne;
  frame.primary = "FLOOR";
  frame.secondary = "SQ_YN";
  frame.tertiary = "BORE";
  frame.z_sense.rule = gdt::AxisSense::Rule::kToward;  // +Z toward the layers above the floor
  frame.z_sense.feature = "CIRCLE";
  frame.x_sense.rule = gdt::AxisSense::Rule::kPointOrder;
  plan.datum_frame = frame;
  auto feature = [&](const std::string& name, FeatureKind kind, gdt::Projection proj = gdt::Projection::kNone) {
    gdt::FeatureSpec f;
    f.name = name;
    f.kind = kind;
    f.projection = proj;
    if (kind == FeatureKind::kPlane) f.nominal_direction = Eigen::Vector3d::UnitZ();
    plan.features.push_back(f);
  };
  auto charac = [&](const std::string& name, CharacteristicType type, const std::string& f, const std::string& datum,
                    const std::string& description) -> gdt::CharacteristicSpec& {
    gdt::CharacteristicSpec c;
    c.name = name;
    c.type = type;
    c.feature = f;
    c.datum = datum;
    c.description = description;
    plan.characteristics.push_back(c);
    return plan.characteristics.back();
  };
  feature("FLOOR", FeatureKind::kPlane);
  for (const char* n : {"SQ_YN", "SQ_XP", "SQ_YP", "SQ_XN", "DI_1", "DI_2", "DI_3", "DI_4", "SL3", "SLX_P", "SL6", "SLX_N"}) {
    feature(n, FeatureKind::kLine3);
  }
  feature("CIRCLE", FeatureKind::kCircle, gdt::Projection::kDatumXY);
  feature("BORE", FeatureKind::kCircle, gdt::Projection::kDatumXY);

  charac("flatness_FLOOR", CharacteristicType::kFlatness, "FLOOR", "", "flatness of the base top");
  for (const char* n : {"SQ_YN", "SQ_XP", "SQ_YP", "SQ_XN", "DI_1", "DI_2", "DI_3", "DI_4", "SL3", "SLX_P", "SL6", "SLX_N"}) {
    charac(std::string("straightness_") + n, CharacteristicType::kStraightness, n, "", std::string("straightness of ") + n);
  }
  charac("squareness_SQ_XP_SQ_YN", CharacteristicType::kSquareness, "SQ_XP", "SQ_YN", "square: +X side to -Y side");
  charac("squareness_SQ_YP_SQ_XP", CharacteristicType::kSquareness, "SQ_YP", "SQ_XP", "square: +Y side to +X side");
  charac("squareness_SQ_XN_SQ_YP", CharacteristicType::kSquareness, "SQ_XN", "SQ_YP", "square: -X side to +Y side");
  charac("parallelism_SQ_YP_SQ_YN", CharacteristicType::kParallelism, "SQ_YP", "SQ_YN", "square: +Y side to -Y side");
  charac("parallelism_SQ_XN_SQ_XP", CharacteristicType::kParallelism, "SQ_XN", "SQ_XP", "square: -X side to +X side");
  charac("squareness_DI_2_DI_1", CharacteristicType::kSquareness, "DI_2", "DI_1", "diamond: adjacent sides");
  charac("parallelism_DI_3_DI_1", CharacteristicType::kParallelism, "DI_3", "DI_1", "diamond: opposite sides");
  charac("parallelism_DI_4_DI_2", CharacteristicType::kParallelism, "DI_4", "DI_2", "diamond: opposite sides");
  charac("circularity_CIRCLE", CharacteristicType::kCircularity, "CIRCLE", "", "circularity of the circle boss");
  charac("size_CIRCLE", CharacteristicType::kSize, "CIRCLE", "", "radius of the circle boss").nominal_radius_mm =
      0.5 * p.circle_diameter_mm;
  charac("concentricity_CIRCLE_BORE", CharacteristicType::kConcentricity, "CIRCLE", "BORE",
         "circle boss to the bore (contour vs bore interpolation)");
  charac("circularity_BORE", CharacteristicType::kCircularity, "BORE", "", "circularity of the bore");
  charac("size_BORE", CharacteristicType::kSize, "BORE", "", "radius of the bore").nominal_radius_mm =
      0.5 * p.bore_diameter_mm;
  charac("position_BORE", CharacteristicType::kPosition, "BORE", "", "bore centre to the -Y side").nominal_xy_mm =
      Eigen::Vector2d(0.0, 0.5 * p.square_side_mm);
  return plan;
}

}  // namespace internal
}  // namespace tpcal::testpieces
