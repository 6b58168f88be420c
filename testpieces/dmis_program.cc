// FormatDmisProgram (dmis_program.h): header, manual datum alignment, DCC points, OUTPUT.
#include "testpieces/dmis_program.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <vector>

namespace tpcal::testpieces {
namespace {

std::string DmisNum(double v) {
  if (std::abs(v) < 5e-7) v = 0.0;  // no "-0.000000"
  return fmt::format("{:.6f}", v);
}

std::string Xyz(const Eigen::Vector3d& p) { return DmisNum(p.x()) + "," + DmisNum(p.y()) + "," + DmisNum(p.z()); }

bool DmisLabelOk(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s)
    if (!((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-'))
      return false;
  return true;
}

struct FeaturePoints {
  std::vector<Eigen::Vector3d> p, n;
};

Eigen::Vector3d Centroid(const std::vector<Eigen::Vector3d>& v) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& x : v) c += x;
  return c / static_cast<double>(std::max<std::size_t>(v.size(), 1));
}

// Unit eigenvector of the smallest eigenvalue of sum (v - mean)(v - mean)^T (mean removed if asked).
Eigen::Vector3d LeastSpread(const std::vector<Eigen::Vector3d>& v, bool centre) {
  const Eigen::Vector3d c = centre ? Centroid(v) : Eigen::Vector3d::Zero();
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  for (const auto& x : v) m += (x - c) * (x - c).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(m);
  return es.eigenvectors().col(0).normalized();
}

// Sign so the largest component is positive (a deterministic sense for axes).
Eigen::Vector3d Canonical(Eigen::Vector3d a) {
  Eigen::Index i = 0;
  a.cwiseAbs().maxCoeff(&i);
  return a[i] < 0 ? Eigen::Vector3d(-a) : a;
}

// `F(name)=FEAT/...` nominal of a datum feature from its planned points (datum frame).
Result<std::string> NominalFeat(const std::string& name, gdt::FeatureKind kind, gdt::Projection proj,
                                const FeaturePoints& f, std::string* dmis_type) {
  const Eigen::Vector3d c = Centroid(f.p);
  const Eigen::Vector3d mean_n = Centroid(f.n);
  auto radial = [&](const Eigen::Vector3d& axis, double* radius, bool* outer) {
    double r = 0, out = 0;
    for (std::size_t i = 0; i < f.p.size(); ++i) {
      Eigen::Vector3d d = f.p[i] - c;
      d -= d.dot(axis) * axis;
      r += d.norm();
      out += d.dot(f.n[i]);
    }
    *radius = r / static_cast<double>(f.p.size());
    *outer = out > 0;
  };
  switch (kind) {
    case gdt::FeatureKind::kPlane:
      *dmis_type = "PLANE";
      return fmt::format("F({})=FEAT/PLANE,CART,{},{}", name, Xyz(c), Xyz(mean_n.normalized()));
    case gdt::FeatureKind::kCircle:
    case gdt::FeatureKind::kCylinder: {
      Eigen::Vector3d axis = proj == gdt::Projection::kDatumXY   ? Eigen::Vector3d::UnitZ()
                             : proj == gdt::Projection::kDatumYZ ? Eigen::Vector3d::UnitX()
                             : proj == gdt::Projection::kDatumZX ? Eigen::Vector3d::UnitY()
                             : kind == gdt::FeatureKind::kCircle ? Canonical(LeastSpread(f.p, true))
                                                                 : Canonical(LeastSpread(f.n, false));
      double radius = 0;
      bool outer = true;
      radial(axis, &radius, &outer);
      *dmis_type = kind == gdt::FeatureKind::kCircle ? "CIRCLE" : "CYLNDR";
      return fmt::format("F({})=FEAT/{},{},CART,{},{},{}", name, *dmis_type, outer ? "OUTER" : "INNER", Xyz(c),
                         Xyz(axis), DmisNum(2 * radius));
    }
    case gdt::FeatureKind::kLine3:
    case gdt::FeatureKind::kLine2:
      *dmis_type = "LINE";
      return fmt::format("F({})=FEAT/LINE,BND,CART,{},{},{}", name, Xyz(f.p.front()), Xyz(f.p.back()),
                         Xyz(mean_n.normalized()));
    case gdt::FeatureKind::kPoint:
      *dmis_type = "POINT";
      return fmt::format("F({})=FEAT/POINT,CART,{},{}", name, Xyz(f.p.front()), Xyz(f.n.front()));
    default:
      return Status(StatusCode::kInvalidArgument,
                    fmt::format("datum feature {}: a DMIS alignment on this feature kind is not supported "
                                "(expected a plane, circle, cylinder, line or point)", name));
  }
}

}  // namespace

std::string DmisPointLabel(const std::string& feature, int k) { return fmt::format("{}_{}", feature, k); }

Result<std::string> FormatDmisProgram(const TestPiece& piece, const ProbingPlan& plan,
                                      const DmisProgramOptions& options) {
  if (!(options.approach_mm > 0) || !(options.clearance_mm > 0))
    return Status(StatusCode::kInvalidArgument, "DMIS program: approach_mm and clearance_mm must be > 0");
  if (!piece.inspection.datum_frame.has_value())
    return Status(StatusCode::kInvalidArgument,
                  fmt::format("DMIS program: piece {} has no datum frame to align on", piece.name));
  const PointSet ps = PlanPointSet(plan);
  std::map<std::string, FeaturePoints> by_feature;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const std::string& f = ps.feature_names[static_cast<std::size_t>(ps.feature[i])];
    if (!DmisLabelOk(f))
      return Status(StatusCode::kInvalidArgument,
                    fmt::format("DMIS program: feature name '{}': expected letters, digits, '_' or '-'", f));
    by_feature[f].p.push_back(ps.xyz_mm[i]);
    by_feature[f].n.push_back(ps.normal[i]);
  }

  std::string out;
  auto app = std::back_inserter(out);
  fmt::format_to(app,
                 "$$ tpcal DMIS inspection program: test piece {}, {} points on {} features\n"
                 "$$ written by `tpcal plan --dmis` (docs/formats/dmis.md). Coordinates: the piece's datum frame, mm.\n"
                 "$$ Each point is F(<feature>_<k>); its actual comes back as FA(<feature>_<k>) in the .dmo.\n"
                 "$$ Moves are straight lines: check the program in the CMM software's simulation first.\n"
                 "DMISMN/'tpcal {} probing plan',05.3\n"
                 "FILNAM/'{}',05.3\n"
                 "UNITS/MM,ANGDEC\n"
                 "WKPLAN/XYPLAN\n"
                 "SNSET/APPRCH,{}\n"
                 "SNSET/RETRCT,{}\n",
                 piece.name, ps.size(), ps.feature_names.size(), piece.name, piece.name, DmisNum(options.approach_mm),
                 DmisNum(options.approach_mm));

  // (1) Manual alignment on the datum features.
  const gdt::DatumFrameSpec& frame = *piece.inspection.datum_frame;
  out += "$$ 1. Manual alignment: probe each datum feature at the points shown.\nMODE/MAN\n";
  auto measure_datum = [&](const std::string& name) -> Result<std::string> {
    const gdt::FeatureSpec* spec = piece.inspection.FindFeature(name);
    auto it = by_feature.find(name);
    if (spec == nullptr || it == by_feature.end())
      return Status(StatusCode::kInvalidArgument,
                    fmt::format("DMIS program: datum feature '{}' is not in the probing plan", name));
    std::string type;
    auto feat = NominalFeat(name, spec->kind, spec->projection, it->second, &type);
    if (!feat.ok()) return feat.status();
    fmt::format_to(app, "{}\nMEAS/{},F({}),{}\n", *feat, type, name, it->second.p.size());
    for (std::size_t i = 0; i < it->second.p.size(); ++i)
      fmt::format_to(app, "PTMEAS/CART,{},{}\n", Xyz(it->second.p[i]), Xyz(it->second.n[i]));
    out += "ENDMES\n";
    return type;
  };
  // A line from the centre of `from` to the centre of `to` (or to its first point), for a direction.
  auto direction_line = [&](const std::string& from, const std::string& to, bool first_point, const char* dat) {
    const Eigen::Vector3d a = Centroid(by_feature[from].p);
    const Eigen::Vector3d b = first_point ? by_feature[to].p.front() : Centroid(by_feature[to].p);
    const std::string target = first_point ? "TPCAL_DIR_POINT" : to;
    if (first_point)
      fmt::format_to(app, "F(TPCAL_DIR_POINT)=FEAT/POINT,CART,{},{}\nMEAS/POINT,F(TPCAL_DIR_POINT),1\n"
                          "PTMEAS/CART,{},{}\nENDMES\n",
                     Xyz(b), Xyz(by_feature[to].n.front()), Xyz(b), Xyz(by_feature[to].n.front()));
    fmt::format_to(app, "F(TPCAL_DIR)=FEAT/LINE,UNBND,CART,{},{},{}\nCONST/LINE,F(TPCAL_DIR),BF,FA({}),FA({})\n"
                        "DATDEF/FA(TPCAL_DIR),DAT({})\n",
                   Xyz(a), Xyz((b - a).normalized()), Xyz(Eigen::Vector3d::UnitZ()), from, target, dat);
  };
  std::string datset;
  auto need = [&](const std::string& f) -> Status {
    auto r = measure_datum(f);
    return r.ok() ? Status::Ok() : r.status();
  };
  if (frame.type == gdt::DatumFrameType::kThreeTwoOne) {
    TPCAL_RETURN_IF_ERROR(need(frame.primary));
    fmt::format_to(app, "DATDEF/FA({}),DAT(A)\n", frame.primary);
    TPCAL_RETURN_IF_ERROR(need(frame.secondary));
    fmt::format_to(app, "DATDEF/FA({}),DAT(B)\n", frame.secondary);
    TPCAL_RETURN_IF_ERROR(need(frame.tertiary));
    fmt::format_to(app, "DATDEF/FA({}),DAT(C)\n", frame.tertiary);
    datset = "DAT(A),ZDIR,ZORIG,DAT(B),XDIR,YORIG,DAT(C),XORIG";
  } else {  // turning and datum targets: primary Z, centre XY origin, a direction feature
    TPCAL_RETURN_IF_ERROR(need(frame.primary));
    fmt::format_to(app, "DATDEF/FA({}),DAT(A)\n", frame.primary);
    const bool own_centre = frame.center != frame.primary;
    if (own_centre) {
      TPCAL_RETURN_IF_ERROR(need(frame.center));
      fmt::format_to(app, "DATDEF/FA({}),DAT(B)\n", frame.center);
    }
    const gdt::FeatureSpec* centre_spec = piece.inspection.FindFeature(frame.center);
    if (centre_spec != nullptr && centre_spec->kind == gdt::FeatureKind::kPlane)
      fmt::format_to(app, "$$ note: tpcal's X, Y origin is the centroid of {}'s planned points (DMIS has no plane "
                          "centre): set it by hand if the CMM software does not take it from DAT({})\n",
                     frame.center, own_centre ? "B" : "A");
    const bool y_dir = !frame.y_toward.empty();
    const std::string toward = y_dir ? frame.y_toward : frame.x_toward;
    if (toward != frame.center && toward != frame.primary) TPCAL_RETURN_IF_ERROR(need(toward));
    direction_line(frame.center, toward, frame.toward_first_point, "C");
    datset = std::string("DAT(A),ZDIR,ZORIG,") + (own_centre ? "DAT(B)" : "DAT(A)") + ",XORIG,YORIG,DAT(C)," +
             (y_dir ? "YDIR" : "XDIR");
  }
  fmt::format_to(app, "D(TPCAL_DATUM)=DATSET/{}\n", datset);

  // (2) DCC: every planned point, in plan order.
  double z_safe = -1e300;
  for (std::size_t i = 0; i < ps.size(); ++i)
    z_safe = std::max(z_safe, (ps.xyz_mm[i] + options.approach_mm * ps.normal[i]).z());
  z_safe += options.clearance_mm;
  out += "$$ 2. DCC measurement of every planned point.\nMODE/AUTO,PROG,MAN\n";
  std::map<std::string, int> count;
  std::vector<std::string> labels;
  labels.reserve(ps.size());
  int last_feature = PointSet::kUnlabelled - 1;
  Eigen::Vector3d last_approach = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const std::string& f = ps.feature_names[static_cast<std::size_t>(ps.feature[i])];
    const std::string label = DmisPointLabel(f, ++count[f]);
    const Eigen::Vector3d approach = ps.xyz_mm[i] + options.approach_mm * ps.normal[i];
    if (ps.feature[i] != last_feature) {
      if (i > 0)
        fmt::format_to(app, "GOTO/CART,{},{},{}\n", DmisNum(last_approach.x()), DmisNum(last_approach.y()), DmisNum(z_safe));
      fmt::format_to(app, "$$ feature {}\nGOTO/CART,{},{},{}\n", f, DmisNum(approach.x()), DmisNum(approach.y()), DmisNum(z_safe));
      last_feature = ps.feature[i];
    }
    fmt::format_to(app, "F({})=FEAT/POINT,CART,{},{}\nMEAS/POINT,F({}),1\nGOTO/CART,{}\nPTMEAS/CART,{},{}\nGOTO/CART,{}\nENDMES\n",
                   label, Xyz(ps.xyz_mm[i]), Xyz(ps.normal[i]), label, Xyz(approach), Xyz(ps.xyz_mm[i]),
                   Xyz(ps.normal[i]), Xyz(approach));
    last_approach = approach;
    labels.push_back(label);
  }
  fmt::format_to(app, "GOTO/CART,{},{},{}\n", DmisNum(last_approach.x()), DmisNum(last_approach.y()), DmisNum(z_safe));

  // (3) Every actual to the output file.
  out += "$$ 3. Output of every point actual (FA) to the .dmo.\n";
  for (const std::string& l : labels) fmt::format_to(app, "OUTPUT/FA({})\n", l);
  out += "ENDFIL\n";
  return out;
}

}  // namespace tpcal::testpieces
