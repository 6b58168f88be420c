// OpenCASCADE stays in this file (GUIDE: third-party libraries behind the module that needs them).
#include "testpieces/brep.h"

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepGProp.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCone.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <BRepPrimAPI_MakeRevol.hxx>
#include <Bnd_Box.hxx>
#include <GProp_GProps.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Gravity.hxx>
#include <Message_Messenger.hxx>
#include <Message_Printer.hxx>
#include <STEPControl_Writer.hxx>
#include <Standard_Failure.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Shape.hxx>
#include <gp_Ax1.hxx>
#include <gp_Ax2.hxx>
#include <gp_Pnt.hxx>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/units.h"

namespace tpcal::testpieces {
namespace internal {
std::vector<Eigen::Vector2d> SquareOutline(double side);
std::vector<Eigen::Vector2d> DiamondOutline(double side);
std::vector<Eigen::Vector2d> SlopeOutline(const ContourPieceParams& p);
}  // namespace internal

namespace {

gp_Pnt P(const Eigen::Vector3d& v) { return gp_Pnt(v.x(), v.y(), v.z()); }

TopoDS_Shape Check(const TopoDS_Shape& s, const char* what) {
  if (s.IsNull()) throw Standard_Failure(what);
  return s;
}

TopoDS_Shape Fuse(const TopoDS_Shape& a, const TopoDS_Shape& b) {
  BRepAlgoAPI_Fuse op(a, b);
  if (!op.IsDone()) throw Standard_Failure("boolean fuse failed");
  return Check(op.Shape(), "boolean fuse");
}

TopoDS_Shape Cut(const TopoDS_Shape& a, const TopoDS_Shape& b) {
  BRepAlgoAPI_Cut op(a, b);
  if (!op.IsDone()) throw Standard_Failure("boolean cut failed");
  return Check(op.Shape(), "boolean cut");
}

// Planar face from a closed polygon (points in order).
TopoDS_Face PolygonFace(const std::vector<Eigen::Vector3d>& pts) {
  BRepBuilderAPI_MakePolygon poly;
  for (const auto& q : pts) poly.Add(P(q));
  poly.Close();
  BRepBuilderAPI_MakeFace face(poly.Wire(), Standard_True);
  if (!face.IsDone()) throw Standard_Failure("polygon face");
  return face.Face();
}

// Prism of an XY outline between z0 and z1.
TopoDS_Shape Extrude(const std::vector<Eigen::Vector2d>& outline, double z0, double z1) {
  std::vector<Eigen::Vector3d> pts;
  for (const auto& q : outline) pts.emplace_back(q.x(), q.y(), z0);
  BRepPrimAPI_MakePrism prism(PolygonFace(pts), gp_Vec(0, 0, z1 - z0));
  return Check(prism.Shape(), "prism");
}

TopoDS_Shape ZCylinder(double x, double y, double r, double z0, double z1) {
  return Check(BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(x, y, z0), gp_Dir(0, 0, 1)), r, z1 - z0).Shape(), "cylinder");
}

TopoDS_Shape TurningSolid(const TurningPieceParams& p) {
  // Axisymmetric profile in the XZ half plane (x = radius), revolved about Z: body, steps,
  // groove and bore in one sweep; the holes are cut afterwards.
  std::vector<Eigen::Vector3d> prof;
  auto add = [&](double r, double z) { prof.emplace_back(r, 0.0, z); };
  const double z_top = p.top_z_mm();
  add(p.bore_radius_mm, p.base_bottom_z_mm);
  add(p.base_radius_mm, p.base_bottom_z_mm);
  for (int i = 5; i >= 0; --i) {
    add(p.BottomOuterRadius(i), p.steps[i].shoulder_z_mm);
    add(p.steps[i].radius_mm, p.steps[i].shoulder_z_mm);
  }
  add(p.steps[0].radius_mm, z_top);
  add(p.groove_outer_radius_mm, z_top);
  add(p.groove_outer_radius_mm, p.groove_bottom_z_mm);
  add(p.groove_inner_radius_mm, p.groove_bottom_z_mm);
  add(p.groove_inner_radius_mm, z_top);
  add(0.0, z_top);
  if (p.bore_radius_mm > 0) {
    add(0.0, p.bore_top_z_mm);
    add(p.bore_radius_mm, p.bore_top_z_mm);
  }
  BRepPrimAPI_MakeRevol revol(PolygonFace(prof), gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), 2.0 * M_PI);
  TopoDS_Shape solid = Check(revol.Shape(), "revolution");
  for (int k = 0; k < p.hole_count; ++k) {
    const double c = 2.0 * kPi * k / p.hole_count;
    solid = Cut(solid, ZCylinder(p.hole_pitch_radius_mm * std::cos(c), p.hole_pitch_radius_mm * std::sin(c),
                                 0.5 * p.reamer_diameter_mm, z_top - p.hole_depth_mm, z_top + 1.0));
  }
  return solid;
}

TopoDS_Shape ContourSolid(const ContourPieceParams& p) {
  const double b = p.floor_z_mm();
  const double z_sq = b + p.square_height_mm, z_di = z_sq + p.diamond_height_mm;
  const double z_ci = z_di + p.circle_height_mm, z_top = z_ci + p.slope_height_mm;
  TopoDS_Shape s = Extrude(internal::SquareOutline(p.size_mm), 0.0, b);
  s = Fuse(s, Extrude(internal::SquareOutline(p.square_side_mm), b, z_sq));
  s = Fuse(s, Extrude(internal::DiamondOutline(p.diamond_side_mm), z_sq, z_di));
  s = Fuse(s, ZCylinder(0, 0, 0.5 * p.circle_diameter_mm, z_di, z_ci));
  s = Fuse(s, Extrude(internal::SlopeOutline(p), z_ci, z_top));
  return Cut(s, ZCylinder(0, 0, 0.5 * p.bore_diameter_mm, b, z_top + 1.0));
}

TopoDS_Shape FaceMillingSolid(const FaceMillingPieceParams& p) {
  const double w = p.width_mm();
  return Check(BRepPrimAPI_MakeBox(gp_Pnt(-0.5 * p.length_mm, -0.5 * w, 0.0), p.length_mm, w, p.height_mm).Shape(),
               "box");
}

// One cone frustum standing on the base top, from its first section's feature.
TopoDS_Shape ConeOf(const NominalFeature& cone_feature, const ConeFrustumParams& p) {
  const NominalFeature* cone = &cone_feature;
  const double t = p.base_thickness_mm;
  // Extend the cone below the base top far enough that its bottom circle lies inside the base.
  const double a = cone->half_angle_rad;
  const double tau = std::acos(std::clamp(cone->axis.z(), -1.0, 1.0));
  const double e = cone->radius_mm * std::sin(tau) / (std::cos(tau) - std::tan(a) * std::sin(tau)) + 1.0;
  const double r_bottom = cone->radius_mm + e * std::tan(a);
  const double r_top = cone->radius_mm - p.height_mm * std::tan(a);
  if (t - e * std::cos(tau) - r_bottom * std::sin(tau) <= 0) throw Standard_Failure("base too thin for the tilted cone");
  const Eigen::Vector3d o = cone->origin_mm - e * cone->axis;
  gp_Ax2 ax(P(o), gp_Dir(cone->axis.x(), cone->axis.y(), cone->axis.z()),
            gp_Dir(cone->ref_dir.x(), cone->ref_dir.y(), cone->ref_dir.z()));
  return Check(BRepPrimAPI_MakeCone(ax, r_bottom, r_top, e + p.height_mm).Shape(), "cone");
}

TopoDS_Shape ConeSolid(const TestPiece& piece, const ConeFrustumParams& p) {
  const NominalFeature* cone = piece.Feature("CONE_1");
  if (!cone) throw Standard_Failure("cone feature missing");
  const double t = p.base_thickness_mm;
  TopoDS_Shape s = Check(
      BRepPrimAPI_MakeBox(gp_Pnt(-0.5 * p.base_size_mm, -0.5 * p.base_size_mm, 0.0), p.base_size_mm, p.base_size_mm, t)
          .Shape(),
      "base");
  s = Fuse(s, ConeOf(*cone, p));
  if (const NominalFeature* second = piece.Feature("CONE2_1")) s = Fuse(s, ConeOf(*second, p));
  if (const NominalFeature* third = piece.Feature("CONE3_1")) s = Fuse(s, ConeOf(*third, p));
  return s;
}

TopoDS_Shape BuildSolid(const TestPiece& piece) {
  const PieceParams& params = piece.config.params;
  if (const auto* p = std::get_if<TurningPieceParams>(&params)) return TurningSolid(*p);
  if (const auto* p = std::get_if<ContourPieceParams>(&params)) return ContourSolid(*p);
  if (const auto* p = std::get_if<FaceMillingPieceParams>(&params)) return FaceMillingSolid(*p);
  return ConeSolid(piece, std::get<ConeFrustumParams>(params));
}

Result<TopoDS_Shape> SolidOf(const TestPiece& piece) {
  try {
    return BuildSolid(piece);
  } catch (const Standard_Failure& f) {
    return Status(StatusCode::kInternal, std::string("OpenCASCADE: building the solid of '") + piece.name +
                                             "' failed: " + (f.GetMessageString() ? f.GetMessageString() : "?"));
  }
}

}  // namespace

namespace {

// Libraries do not print: OpenCASCADE's STEP writer reports its statistics through the default
// messenger, so its printers are raised to failures only for the duration of a write.
class QuietMessenger {
 public:
  QuietMessenger() {
    const Handle(Message_Messenger)& m = Message::DefaultMessenger();
    for (Message_SequenceOfPrinters::Iterator it(m->Printers()); it.More(); it.Next()) {
      levels_.push_back(it.Value()->GetTraceLevel());
      it.Value()->SetTraceLevel(Message_Fail);
    }
  }
  ~QuietMessenger() {
    const Handle(Message_Messenger)& m = Message::DefaultMessenger();
    std::size_t i = 0;
    for (Message_SequenceOfPrinters::Iterator it(m->Printers()); it.More() && i < levels_.size(); it.Next(), ++i) {
      it.Value()->SetTraceLevel(levels_[i]);
    }
  }

 private:
  std::vector<Message_Gravity> levels_;
};

}  // namespace

Status WriteStep(const TestPiece& piece, const std::string& path) {
  auto solid = SolidOf(piece);
  if (!solid.ok()) return solid.status();
  QuietMessenger quiet;
  try {
    STEPControl_Writer writer;
    Interface_Static::SetCVal("write.step.schema", "AP214IS");
    Interface_Static::SetCVal("write.step.unit", "MM");
    if (writer.Transfer(*solid, STEPControl_AsIs) != IFSelect_RetDone) {
      return Status(StatusCode::kInternal, "OpenCASCADE: STEP transfer failed", path);
    }
    if (writer.Write(path.c_str()) != IFSelect_RetDone) {
      return Status(StatusCode::kIoError, "cannot write the STEP file", path);
    }
  } catch (const Standard_Failure& f) {
    return Status(StatusCode::kInternal, std::string("OpenCASCADE: STEP export failed: ") +
                                             (f.GetMessageString() ? f.GetMessageString() : "?"), path);
  }
  return Status::Ok();
}

Result<BrepSummary> SummarizeBrep(const TestPiece& piece) {
  auto solid = SolidOf(piece);
  if (!solid.ok()) return solid.status();
  BrepSummary s;
  GProp_GProps props;
  BRepGProp::VolumeProperties(*solid, props);
  s.volume_mm3 = props.Mass();
  for (TopExp_Explorer ex(*solid, TopAbs_FACE); ex.More(); ex.Next()) ++s.num_faces;
  Bnd_Box box;
  BRepBndLib::AddOptimal(*solid, box, Standard_False, Standard_False);
  double x0, y0, z0, x1, y1, z1;
  box.Get(x0, y0, z0, x1, y1, z1);
  s.box_min_mm = Eigen::Vector3d(x0, y0, z0);
  s.box_max_mm = Eigen::Vector3d(x1, y1, z1);
  return s;
}

Result<std::vector<BrepPointCheck>> CheckPointsOnBrep(const TestPiece& piece,
                                                      const std::vector<Eigen::Vector3d>& points_part_mm,
                                                      const std::vector<Eigen::Vector3d>& normals_part, double step_mm,
                                                      double distance_tol_mm) {
  if (points_part_mm.size() != normals_part.size()) {
    return Status(StatusCode::kInvalidArgument, "CheckPointsOnBrep: points and normals differ in count");
  }
  auto solid = SolidOf(piece);
  if (!solid.ok()) return solid.status();
  std::vector<BrepPointCheck> out;
  out.reserve(points_part_mm.size());
  try {
    BRepClass3d_SolidClassifier classifier(*solid);
    // Classification tolerance well below the step (1e-7 mm).
    constexpr double kClassTol_mm = 1e-7;
    for (std::size_t i = 0; i < points_part_mm.size(); ++i) {
      BrepPointCheck c;
      BRepExtrema_DistShapeShape dist(*solid, BRepBuilderAPI_MakeVertex(P(points_part_mm[i])).Vertex());
      if (!dist.IsDone()) return Status(StatusCode::kInternal, "OpenCASCADE: distance computation failed");
      c.distance_mm = dist.Value();
      classifier.Perform(P(points_part_mm[i] + step_mm * normals_part[i]), kClassTol_mm);
      c.outside_plus = classifier.State() == TopAbs_OUT;
      classifier.Perform(P(points_part_mm[i] - step_mm * normals_part[i]), kClassTol_mm);
      c.inside_minus = classifier.State() == TopAbs_IN;
      c.ok = c.distance_mm <= distance_tol_mm && c.outside_plus && c.inside_minus;
      out.push_back(c);
    }
  } catch (const Standard_Failure& f) {
    return Status(StatusCode::kInternal, std::string("OpenCASCADE: point check failed: ") +
                                             (f.GetMessageString() ? f.GetMessageString() : "?"));
  }
  return out;
}

}  // namespace tpcal::testpieces
