#include "gdt/characteristic.h"

#include <cmath>

#include "core/units.h"
#include "gdt/form.h"
#include "gdt/form_zone.h"
#include "gdt/hole_pattern.h"
#include "gdt/location.h"
#include "gdt/orientation.h"

namespace tpcal::gdt {
namespace {

using fitting::Circle2;
using fitting::Line2;
using fitting::Plane;

constexpr const char* kAbc = "abc";  // rotation letters about X, Y, Z (ISO 230-1 A, B, C)

std::vector<Eigen::Vector3d> Gather(std::span<const Eigen::Vector3d> all, const std::vector<std::size_t>& idx) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(idx.size());
  for (std::size_t i : idx) out.push_back(all[i]);
  return out;
}

class Builder {
 public:
  explicit Builder(CharacteristicResult* r) : r_(r) {}
  void Um(const std::string& name, double mm) { r_->values.push_back({name, MmToUm(mm), "um"}); }
  void Urad(const std::string& name, double rad) { r_->values.push_back({name, RadToUrad(rad), "urad"}); }
  void Mm(const std::string& name, double mm) { r_->values.push_back({name, mm, "mm"}); }

 private:
  CharacteristicResult* r_;
};

Status WrongKind(const FittedFeature& f, const char* expected) {
  return Status(StatusCode::kInvalidArgument, "feature '" + f.name + "' is a " + FeatureKindName(f.kind) +
                                                  ", expected " + expected);
}

std::string RotName(int axis) { return std::string("d") + kAbc[axis] + "_urad"; }

// The form value under `criterion`, from the feature when it already holds it, else computed.
// A minimum-zone value that is not certified optimal is kept (it is a valid enclosing zone)
// and said so in the note.
template <typename ComputeMz>
Result<double> FormValue(FormCriterion criterion, const FittedFeature& f, double ls_mm, CharacteristicResult* out,
                         ComputeMz&& compute_mz) {
  if (criterion == FormCriterion::kLeastSquares) return ls_mm;
  Result<MinimumZoneValue> mz = f.form_mz ? Result<MinimumZoneValue>(*f.form_mz) : compute_mz();
  if (!mz.ok()) return mz.status();
  if (!mz->verified_optimal) out->note = "minimum zone not certified optimal (" + mz->note + ")";
  return mz->width_mm;
}

// Representative points of a directed feature for orientation zones: measured points of planes
// and lines, the two axis end points (over the points' extent) of a cylinder.
std::vector<Eigen::Vector3d> DirectedPoints(const FittedFeature& f, std::span<const Eigen::Vector3d> all) {
  std::vector<Eigen::Vector3d> pts = Gather(all, f.point_indices);
  if (const auto* c = f.As<fitting::Cylinder>()) {
    double lo = 0, hi = 0;
    bool first = true;
    for (const auto& p : pts) {
      const double t = c->feature.axis.dot(p - c->feature.point_mm);
      lo = first ? t : std::min(lo, t);
      hi = first ? t : std::max(hi, t);
      first = false;
    }
    return {c->feature.point_mm + c->feature.axis * lo, c->feature.point_mm + c->feature.axis * hi};
  }
  return pts;
}

Status EvalConcentricity(const CharacteristicSpec& s, const FittedFeature& f, const FittedFeature& d, Builder& b) {
  auto cf = CenterInPlane(f, s.plane);
  if (!cf.ok()) return cf.status();
  auto cd = CenterInPlane(d, s.plane);
  if (!cd.ok()) return cd.status();
  const PlanarOffset off = CenterOffset(*cf, *cd);
  const auto [u, v] = AxisLetters(s.plane);
  b.Um(std::string("d") + u + "_um", off.delta_mm.x());
  b.Um(std::string("d") + v + "_um", off.delta_mm.y());
  b.Um("zone_diameter_um", off.zone_diameter_mm);
  return Status::Ok();
}

Status EvalPosition(const CharacteristicSpec& s, const FittedFeature& f, Builder& b) {
  if (s.nominal_xyz_mm) {
    auto c = CenterOf(f);
    if (!c.ok()) return c.status();
    const Eigen::Vector3d d = *c - *s.nominal_xyz_mm;
    b.Mm("x_mm", c->x());
    b.Mm("y_mm", c->y());
    b.Mm("z_mm", c->z());
    b.Um("dx_um", d.x());
    b.Um("dy_um", d.y());
    b.Um("dz_um", d.z());
    b.Um("position_diameter_um", 2.0 * d.norm());
    return Status::Ok();
  }
  Eigen::Vector2d nominal;
  if (s.nominal_xy_mm) {
    nominal = *s.nominal_xy_mm;
  } else if (s.nominal_angle_deg && s.nominal_radius_mm) {
    const double a = DegToRad(*s.nominal_angle_deg);
    nominal = *s.nominal_radius_mm * Eigen::Vector2d(std::cos(a), std::sin(a));
  } else {
    return Status(StatusCode::kInvalidArgument, "a nominal position is required");
  }
  auto c = CenterInPlane(f, s.plane);
  if (!c.ok()) return c.status();
  const PlanarOffset off = CenterOffset(*c, nominal);
  const auto [u, v] = AxisLetters(s.plane);
  b.Mm(std::string(u) + "_mm", c->x());
  b.Mm(std::string(v) + "_mm", c->y());
  b.Um(std::string("d") + u + "_um", off.delta_mm.x());
  b.Um(std::string("d") + v + "_um", off.delta_mm.y());
  b.Um("position_diameter_um", off.zone_diameter_mm);
  return Status::Ok();
}

Status EvalParallelism(const FittedFeature& f, const FittedFeature& d, std::span<const Eigen::Vector3d> all,
                       Builder& b) {
  auto uf = DirectionOf(f);
  if (!uf.ok()) return uf.status();
  auto vd = DirectionOf(d);
  if (!vd.ok()) return vd.status();
  const std::vector<Eigen::Vector3d> pts = Gather(all, f.point_indices);
  if (const auto* pf = f.As<Plane>()) {
    const ParallelismResult r = PlaneParallelism(*uf, pf->feature.point_mm, *vd, pts);
    b.Urad(RotName(r.tilt.axis_i), r.tilt.about_i_rad);
    b.Urad(RotName(r.tilt.axis_j), r.tilt.about_j_rad);
    b.Urad("angle_urad", r.tilt.total_rad);
    b.Um("zone_um", r.zone_mm);
    b.Um("tilt_zone_um", r.tilt_zone_mm);
    return Status::Ok();
  }
  const std::vector<Eigen::Vector3d> ends = DirectedPoints(f, all);
  double lo = 0, hi = 0;
  for (std::size_t i = 0; i < ends.size(); ++i) {
    const double t = uf->dot(ends[i]);
    lo = i == 0 ? t : std::min(lo, t);
    hi = i == 0 ? t : std::max(hi, t);
  }
  const ParallelismResult r = AxisParallelism(*uf, *vd, hi - lo);
  b.Urad(RotName(r.tilt.axis_i), r.tilt.about_i_rad);
  b.Urad(RotName(r.tilt.axis_j), r.tilt.about_j_rad);
  b.Urad("angle_urad", r.tilt.total_rad);
  b.Um("tilt_zone_um", r.tilt_zone_mm);
  return Status::Ok();
}

Status EvalSquareness(const FittedFeature& f, const FittedFeature& d, std::span<const Eigen::Vector3d> all,
                      Builder& b) {
  auto u = DirectionOf(f);
  if (!u.ok()) return u.status();
  auto v = DirectionOf(d);
  if (!v.ok()) return v.status();
  auto kind_of = [](const FittedFeature& x) {
    return x.kind == FeatureKind::kPlane ? DirectedKind::kPlaneNormal : DirectedKind::kAxis;
  };
  const std::vector<Eigen::Vector3d> pts = DirectedPoints(f, all);
  auto r = EvaluateSquareness(kind_of(f), *u, pts, kind_of(d), *v);
  if (!r.ok()) return r.status();
  if (r->angle_rad) {
    b.Urad("angle_urad", *r->angle_rad);
  } else {
    b.Urad(RotName(r->tilt->axis_i), r->tilt->about_i_rad);
    b.Urad(RotName(r->tilt->axis_j), r->tilt->about_j_rad);
    b.Urad("tilt_urad", r->tilt->total_rad);
  }
  b.Um("zone_um", r->zone_mm);
  return Status::Ok();
}

Status EvalCircularity(const CharacteristicSpec& s, const FittedFeature& f, std::span<const Eigen::Vector3d> all,
                       CharacteristicResult* out, Builder& b) {
  auto coords = CircleCoordinates(f, Gather(all, f.point_indices));
  if (!coords.ok()) return coords.status();
  const auto& [uv, circle] = *coords;
  const std::vector<RadialDeviation> profile = CircularityProfile(uv, circle);
  const double ls = ProfileRange(profile);
  const FormCriterion criterion = s.criterion.value_or(f.criterion);
  // A reference, not the binding: clang before 16 cannot capture structured bindings.
  const auto& uv_points = uv;
  auto value = FormValue(criterion, f, ls, out, [&] { return MinimumZoneCircularity(uv_points); });
  if (!value.ok()) return value.status();
  out->criterion = criterion;
  b.Um("circularity_um", *value);
  b.Um("ls_um", ls);
  if (criterion == FormCriterion::kMinimumZone) b.Um("mz_um", *value);
  for (const RadialDeviation& d : profile) {
    const std::size_t index = f.kind == FeatureKind::kPitchCircle ? d.index : f.point_indices[d.index];
    out->profile.push_back({RadToDeg(d.theta_rad), MmToUm(d.dr_mm), index});
  }
  return Status::Ok();
}

Status EvalFlatness(const CharacteristicSpec& s, const FittedFeature& f, std::span<const Eigen::Vector3d> all,
                    CharacteristicResult* out, Builder& b) {
  const auto* p = f.As<Plane>();
  if (p == nullptr) return WrongKind(f, "plane");
  const std::vector<Eigen::Vector3d> pts = Gather(all, f.point_indices);
  const double ls = LsFlatness(pts, p->feature);
  const FormCriterion criterion = s.criterion.value_or(f.criterion);
  auto value = FormValue(criterion, f, ls, out, [&] { return MinimumZoneFlatness(pts); });
  if (!value.ok()) return value.status();
  out->criterion = criterion;
  b.Um("flatness_um", *value);
  b.Um("ls_um", ls);
  if (criterion == FormCriterion::kMinimumZone) b.Um("mz_um", *value);
  return Status::Ok();
}

Status EvalStraightness(const CharacteristicSpec& s, const FittedFeature& f, std::span<const Eigen::Vector3d> all,
                        CharacteristicResult* out, Builder& b) {
  const std::vector<Eigen::Vector3d> pts = Gather(all, f.point_indices);
  const FormCriterion criterion = s.criterion.value_or(f.criterion);
  Result<double> value = Status(StatusCode::kInternal, "unset");
  double ls = 0;
  if (const auto* l2 = f.As<Line2>()) {
    std::vector<Eigen::Vector2d> uv;
    for (const auto& p : pts) uv.push_back(InPlane(p, f.projection));
    ls = LsStraightness2(uv, l2->feature);
    value = FormValue(criterion, f, ls, out, [&] { return MinimumZoneStraightness2(uv); });
  } else if (const auto* l3 = f.As<fitting::Line3>()) {
    ls = LsStraightness3(pts, l3->feature);
    value = FormValue(criterion, f, ls, out, [&] { return MinimumZoneStraightness3(pts); });
  } else {
    return WrongKind(f, "line2 or line3");
  }
  if (!value.ok()) return value.status();
  out->criterion = criterion;
  b.Um("straightness_um", *value);
  b.Um("ls_um", ls);
  if (criterion == FormCriterion::kMinimumZone) b.Um("mz_um", *value);
  return Status::Ok();
}

Status EvalPlaneDistance(const CharacteristicSpec& s, const FittedFeature& f, const FittedFeature& d, Builder& b) {
  if (f.As<Plane>() == nullptr) return WrongKind(f, "plane");
  if (d.As<Plane>() == nullptr) return WrongKind(d, "plane");
  if (!s.nominal_distance_mm) return Status(StatusCode::kInvalidArgument, "nominal_distance_mm is required");
  const PlaneDistanceResult r = PlaneDistance(f.As<Plane>()->feature, d.As<Plane>()->feature, *s.nominal_distance_mm);
  b.Mm("distance_mm", r.distance_mm);
  b.Mm("nominal_distance_mm", *s.nominal_distance_mm);
  b.Um("error_um", r.error_mm);
  b.Um("separation_error_um", r.separation_error_mm);
  return Status::Ok();
}

Status EvalSize(const CharacteristicSpec& s, const FittedFeature& f, Builder& b) {
  auto r = RadiusOf(f);
  if (!r.ok()) return r.status();
  if (!s.nominal_radius_mm && !s.nominal_diameter_mm)
    return Status(StatusCode::kInvalidArgument, "nominal_radius_mm or nominal_diameter_mm is required");
  const double nominal_r = s.nominal_radius_mm ? *s.nominal_radius_mm : 0.5 * *s.nominal_diameter_mm;
  b.Mm("radius_mm", *r);
  b.Mm("diameter_mm", 2.0 * *r);
  b.Mm("nominal_radius_mm", nominal_r);
  b.Um("radius_error_um", *r - nominal_r);
  b.Um("diameter_error_um", 2.0 * (*r - nominal_r));
  return Status::Ok();
}

Status EvalHolePattern(const CharacteristicSpec& s, const FittedFeature& f, Builder& b) {
  const auto* c = f.As<Circle2>();
  if (c == nullptr || f.kind != FeatureKind::kPitchCircle) return WrongKind(f, "pitch_circle");
  if (!s.nominal_radius_mm || (s.nominal_angles_deg.empty() && !(s.first_angle_deg && s.pitch_deg)))
    return Status(StatusCode::kInvalidArgument, "nominal_radius_mm and nominal angles are required");
  std::vector<double> nominal;
  for (std::size_t i = 0; i < f.members.size(); ++i) {
    nominal.push_back(s.nominal_angles_deg.empty() ? DegToRad(*s.first_angle_deg + static_cast<double>(i) * *s.pitch_deg)
                                                   : DegToRad(s.nominal_angles_deg[i]));
  }
  auto r = EvaluateHolePattern(c->feature, f.member_centers_mm, nominal);
  if (!r.ok()) return r.status();
  const auto [u, v] = AxisLetters(f.projection);
  b.Um(std::string("center_d") + u + "_um", c->feature.center_mm.x());
  b.Um(std::string("center_d") + v + "_um", c->feature.center_mm.y());
  b.Mm("radius_mm", c->feature.radius_mm);
  b.Um("radius_error_um", c->feature.radius_mm - *s.nominal_radius_mm);
  b.Urad("mean_angle_error_urad", r->mean_angle_error_rad);
  for (std::size_t i = 0; i < f.members.size(); ++i) {
    b.Urad(f.members[i] + ".angle_error_urad", r->holes[i].angle_error_rad);
    b.Um(f.members[i] + ".radial_error_um", r->holes[i].radial_error_mm);
  }
  return Status::Ok();
}

}  // namespace

std::optional<double> CharacteristicResult::Value(const std::string& n) const {
  for (const NamedValue& v : values)
    if (v.name == n) return v.value;
  return std::nullopt;
}

Result<CharacteristicResult> EvaluateCharacteristic(const CharacteristicSpec& spec,
                                                    const std::map<std::string, const FittedFeature*>& features,
                                                    std::span<const Eigen::Vector3d> points_datum) {
  const std::string what = std::string(CharacteristicTypeName(spec.type)) + " '" + spec.name + "'";
  auto find = [&](const std::string& name) -> const FittedFeature* {
    auto it = features.find(name);
    return it == features.end() ? nullptr : it->second;
  };
  const FittedFeature* f = find(spec.feature);
  if (f == nullptr) return Status(StatusCode::kInvalidArgument, what + ": feature '" + spec.feature + "' was not fitted");
  const FittedFeature* d = nullptr;
  if (!spec.datum.empty()) {
    d = find(spec.datum);
    if (d == nullptr) return Status(StatusCode::kInvalidArgument, what + ": datum '" + spec.datum + "' was not fitted");
  }
  CharacteristicResult out;
  out.name = spec.name;
  out.type = spec.type;
  out.symbol = spec.symbol;
  out.description = spec.description;
  out.features.push_back(spec.feature);
  if (d != nullptr) out.features.push_back(spec.datum);
  Builder b(&out);
  Status st;
  switch (spec.type) {
    case CharacteristicType::kConcentricity: st = EvalConcentricity(spec, *f, *d, b); break;
    case CharacteristicType::kPosition: st = EvalPosition(spec, *f, b); break;
    case CharacteristicType::kParallelism: st = EvalParallelism(*f, *d, points_datum, b); break;
    case CharacteristicType::kSquareness: st = EvalSquareness(*f, *d, points_datum, b); break;
    case CharacteristicType::kCircularity: st = EvalCircularity(spec, *f, points_datum, &out, b); break;
    case CharacteristicType::kFlatness: st = EvalFlatness(spec, *f, points_datum, &out, b); break;
    case CharacteristicType::kStraightness: st = EvalStraightness(spec, *f, points_datum, &out, b); break;
    case CharacteristicType::kPlaneDistance: st = EvalPlaneDistance(spec, *f, *d, b); break;
    case CharacteristicType::kSize: st = EvalSize(spec, *f, b); break;
    case CharacteristicType::kHolePattern: st = EvalHolePattern(spec, *f, b); break;
  }
  if (!st.ok()) return st.WithContext(what);
  return out;
}

}  // namespace tpcal::gdt
