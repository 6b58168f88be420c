#include "gdt/plan.h"

#include <algorithm>
#include <initializer_list>
#include <iterator>
#include <set>

namespace tpcal::gdt {
namespace {

template <typename E, std::size_t N>
std::optional<E> ParseByName(std::string_view s, const std::pair<E, const char*> (&table)[N]) {
  for (const auto& [e, name] : table)
    if (s == name) return e;
  return std::nullopt;
}

const std::pair<FeatureKind, const char*> kKinds[] = {
    {FeatureKind::kLine2, "line2"},   {FeatureKind::kLine3, "line3"},       {FeatureKind::kPlane, "plane"},
    {FeatureKind::kCircle, "circle"}, {FeatureKind::kCylinder, "cylinder"}, {FeatureKind::kSphere, "sphere"},
    {FeatureKind::kCone, "cone"},     {FeatureKind::kPoint, "point"},       {FeatureKind::kPitchCircle, "pitch_circle"},
};
const std::pair<Projection, const char*> kProjections[] = {
    {Projection::kNone, "none"},
    {Projection::kDatumXY, "datum_xy"},
    {Projection::kDatumYZ, "datum_yz"},
    {Projection::kDatumZX, "datum_zx"},
};
const std::pair<FormCriterion, const char*> kCriteria[] = {
    {FormCriterion::kLeastSquares, "ls"},
    {FormCriterion::kMinimumZone, "mz"},
};
const std::pair<CharacteristicType, const char*> kTypes[] = {
    {CharacteristicType::kConcentricity, "concentricity"}, {CharacteristicType::kParallelism, "parallelism"},
    {CharacteristicType::kSquareness, "squareness"},       {CharacteristicType::kCircularity, "circularity"},
    {CharacteristicType::kFlatness, "flatness"},           {CharacteristicType::kStraightness, "straightness"},
    {CharacteristicType::kPosition, "position"},           {CharacteristicType::kPlaneDistance, "plane_distance"},
    {CharacteristicType::kSize, "size"},                   {CharacteristicType::kHolePattern, "hole_pattern"},
};

template <typename E, std::size_t N>
const char* NameOf(E e, const std::pair<E, const char*> (&table)[N]) {
  for (const auto& [v, name] : table)
    if (v == e) return name;
  return "?";
}

bool KindIn(FeatureKind k, std::initializer_list<FeatureKind> allowed) {
  return std::find(allowed.begin(), allowed.end(), k) != allowed.end();
}

std::string KindList(std::initializer_list<FeatureKind> allowed) {
  std::string out;
  for (FeatureKind k : allowed) {
    if (!out.empty()) out += ", ";
    out += FeatureKindName(k);
  }
  return out;
}

class Checker {
 public:
  explicit Checker(const InspectionPlan& plan) : plan_(plan) {}

  Status Error(std::size_t line, const std::string& msg) const {
    return Status(StatusCode::kInvalidArgument, msg, plan_.source, line);
  }

  // The feature `name` referenced by `what` at `line` must exist and be one of `allowed`.
  Result<const FeatureSpec*> Ref(const std::string& name, const std::string& what, std::size_t line,
                                 std::initializer_list<FeatureKind> allowed) const {
    if (name.empty()) return Error(line, what + ": no feature given");
    const FeatureSpec* f = plan_.FindFeature(name);
    if (f == nullptr) return Error(line, what + ": unknown feature '" + name + "'");
    if (!KindIn(f->kind, allowed))
      return Error(line, what + ": feature '" + name + "' is a " + FeatureKindName(f->kind) + ", expected " +
                             KindList(allowed));
    return f;
  }

 private:
  const InspectionPlan& plan_;
};

Status ValidateFeature(const InspectionPlan& plan, const Checker& c, const FeatureSpec& f) {
  const bool planar = f.kind == FeatureKind::kLine2 || f.kind == FeatureKind::kCircle ||
                      f.kind == FeatureKind::kPitchCircle;
  if (!planar && f.projection != Projection::kNone)
    return c.Error(f.line, "feature '" + f.name + "': projection applies to line2, circle and pitch_circle only");
  if ((f.kind == FeatureKind::kLine2 || f.kind == FeatureKind::kPitchCircle) && f.projection == Projection::kNone)
    return c.Error(f.line, "feature '" + f.name + "': a " + FeatureKindName(f.kind) +
                               " needs a projection plane (datum_xy, datum_yz or datum_zx)");
  if (f.nominal_direction && !(f.nominal_direction->norm() > 0.0))
    return c.Error(f.line, "feature '" + f.name + "': nominal_direction must be a non-zero vector");
  if (f.kind == FeatureKind::kCone && f.nominal_direction)
    return c.Error(f.line, "feature '" + f.name + "': a cone's axis points to its wider end; nominal_direction is not used");
  const bool directed = f.kind == FeatureKind::kPlane || f.kind == FeatureKind::kLine2 ||
                        f.kind == FeatureKind::kLine3 || f.kind == FeatureKind::kCylinder ||
                        (f.kind == FeatureKind::kCircle && f.projection == Projection::kNone);
  if (f.nominal_direction && !directed && f.kind != FeatureKind::kCone)
    return c.Error(f.line, "feature '" + f.name + "': nominal_direction applies to planes, lines, cylinders and "
                               "unprojected circles");
  const bool has_form = f.kind != FeatureKind::kPoint && f.kind != FeatureKind::kSphere && f.kind != FeatureKind::kCone;
  if (f.form_criterion == FormCriterion::kMinimumZone && !has_form)
    return c.Error(f.line, "feature '" + f.name + "': form_criterion mz is not available for a " +
                               FeatureKindName(f.kind));
  if (f.kind != FeatureKind::kPitchCircle && !f.members.empty())
    return c.Error(f.line, "feature '" + f.name + "': members apply to pitch_circle only");
  if (f.kind == FeatureKind::kPitchCircle) {
    if (f.members.size() < MinPoints(FeatureKind::kPitchCircle))
      return c.Error(f.line, "feature '" + f.name + "': a pitch_circle needs at least 3 members");
    std::set<std::string> seen;
    for (const std::string& m : f.members) {
      if (!seen.insert(m).second) return c.Error(f.line, "feature '" + f.name + "': member '" + m + "' listed twice");
      auto r = c.Ref(m, "feature '" + f.name + "' member", f.line, {FeatureKind::kCircle});
      if (!r.ok()) return r.status();
      if ((*r)->projection != Projection::kNone && (*r)->projection != f.projection)
        return c.Error(f.line, "feature '" + f.name + "': member '" + m + "' is projected into " +
                                   ProjectionName((*r)->projection) + ", the pitch circle into " +
                                   ProjectionName(f.projection));
    }
  }
  (void)plan;
  return Status::Ok();
}

Status ValidateFrame(const Checker& c, const DatumFrameSpec& d) {
  using K = FeatureKind;
  const std::string what = "datum_frame";
  const std::initializer_list<K> any = {K::kLine2,    K::kLine3, K::kPlane, K::kCircle,
                                        K::kCylinder, K::kSphere, K::kCone,  K::kPoint};
  if (d.type == DatumFrameType::kTargets) {
    TPCAL_RETURN_IF_ERROR(c.Ref(d.primary, what + " primary", d.line, {K::kPlane, K::kCircle}));
    TPCAL_RETURN_IF_ERROR(c.Ref(d.center, what + " center", d.line, any));
    if (d.x_toward.empty() == d.y_toward.empty())
      return c.Error(d.line, what + " (targets): give exactly one of x_toward and y_toward");
    const std::string& toward = d.x_toward.empty() ? d.y_toward : d.x_toward;
    TPCAL_RETURN_IF_ERROR(c.Ref(toward, what + (d.x_toward.empty() ? " y_toward" : " x_toward"), d.line, any));
  } else {
    TPCAL_RETURN_IF_ERROR(c.Ref(d.primary, what + " primary", d.line, {K::kPlane}));
    if (!d.y_toward.empty() || d.toward_first_point)
      return c.Error(d.line, what + ": y_toward and toward_first_point are for targets frames");
  }
  if (d.type == DatumFrameType::kTurning) {
    TPCAL_RETURN_IF_ERROR(c.Ref(d.center, what + " center", d.line, {K::kCircle}));
    TPCAL_RETURN_IF_ERROR(c.Ref(d.x_toward, what + " x_toward", d.line, {K::kCircle, K::kPoint, K::kSphere}));
  } else if (d.type == DatumFrameType::kThreeTwoOne) {
    TPCAL_RETURN_IF_ERROR(c.Ref(d.secondary, what + " secondary", d.line, {K::kLine3}));
    TPCAL_RETURN_IF_ERROR(c.Ref(d.tertiary, what + " tertiary", d.line, {K::kPoint, K::kSphere, K::kCircle}));
  }
  for (const AxisSense* s : {&d.z_sense, &d.x_sense}) {
    if (s->rule == AxisSense::Rule::kAwayFrom || s->rule == AxisSense::Rule::kToward) {
      TPCAL_RETURN_IF_ERROR(c.Ref(s->feature, what + " axis sense", d.line,
                                  {K::kLine2, K::kLine3, K::kPlane, K::kCircle, K::kCylinder, K::kSphere, K::kCone,
                                   K::kPoint}));
    }
  }
  if (d.z_sense.rule == AxisSense::Rule::kPointOrder)
    return c.Error(d.line, what + ": z_sense cannot be point_order (a plane's points have no direction)");
  if (d.type != DatumFrameType::kThreeTwoOne && d.x_sense.rule != AxisSense::Rule::kPointOrder)
    return c.Error(d.line, what + ": x_sense is for 3-2-1 frames; a " + DatumFrameTypeName(d.type) +
                               " frame's +X points toward x_toward");
  return Status::Ok();
}

Status ValidateCharacteristic(const Checker& c, const CharacteristicSpec& ch) {
  using K = FeatureKind;
  using T = CharacteristicType;
  const std::string what = "characteristic '" + ch.name + "'";
  auto feature = [&](std::initializer_list<K> allowed) { return c.Ref(ch.feature, what + " feature", ch.line, allowed); };
  auto datum = [&](std::initializer_list<K> allowed) { return c.Ref(ch.datum, what + " datum", ch.line, allowed); };
  auto no_datum = [&]() -> Status {
    if (!ch.datum.empty()) return c.Error(ch.line, what + ": a " + CharacteristicTypeName(ch.type) + " has no datum");
    return Status::Ok();
  };
  auto plane_matches = [&](const FeatureSpec* f) -> Status {
    if (ch.plane == Projection::kNone) return c.Error(ch.line, what + ": plane must be datum_xy, datum_yz or datum_zx");
    if (f->projection != Projection::kNone && f->projection != ch.plane)
      return c.Error(ch.line, what + ": feature '" + f->name + "' is projected into " + ProjectionName(f->projection) +
                                  ", the characteristic is evaluated in " + ProjectionName(ch.plane));
    return Status::Ok();
  };
  const bool has_criterion = ch.type == T::kCircularity || ch.type == T::kFlatness || ch.type == T::kStraightness;
  if (ch.criterion && !has_criterion)
    return c.Error(ch.line, what + ": criterion applies to circularity, flatness and straightness only");
  const std::initializer_list<K> centred = {K::kCircle, K::kPitchCircle, K::kCylinder, K::kSphere, K::kPoint};

  switch (ch.type) {
    case T::kConcentricity: {
      auto f = feature(centred);
      if (!f.ok()) return f.status();
      auto d = datum(centred);
      if (!d.ok()) return d.status();
      TPCAL_RETURN_IF_ERROR(plane_matches(*f));
      TPCAL_RETURN_IF_ERROR(plane_matches(*d));
      break;
    }
    case T::kPosition: {
      auto f = feature(centred);
      if (!f.ok()) return f.status();
      TPCAL_RETURN_IF_ERROR(no_datum());
      const int n_nominals = (ch.nominal_xy_mm ? 1 : 0) + (ch.nominal_xyz_mm ? 1 : 0) +
                             (ch.nominal_angle_deg || ch.nominal_radius_mm ? 1 : 0);
      if (n_nominals != 1)
        return c.Error(ch.line, what + ": give exactly one of nominal_xy_mm, nominal_xyz_mm, or "
                                       "nominal_radius_mm with nominal_angle_deg");
      if ((ch.nominal_angle_deg.has_value()) != (ch.nominal_radius_mm.has_value()))
        return c.Error(ch.line, what + ": nominal_radius_mm and nominal_angle_deg go together");
      if (!ch.nominal_xyz_mm) TPCAL_RETURN_IF_ERROR(plane_matches(*f));
      break;
    }
    case T::kParallelism: {
      auto f = feature({K::kPlane, K::kLine3, K::kCylinder});
      if (!f.ok()) return f.status();
      auto d = datum({K::kPlane, K::kLine3, K::kCylinder});
      if (!d.ok()) return d.status();
      if (((*f)->kind == K::kPlane) != ((*d)->kind == K::kPlane))
        return c.Error(ch.line, what + ": parallelism is evaluated plane to plane or axis (line3, cylinder) to axis");
      break;
    }
    case T::kSquareness: {
      TPCAL_RETURN_IF_ERROR(feature({K::kPlane, K::kLine3, K::kCylinder}));
      TPCAL_RETURN_IF_ERROR(datum({K::kPlane, K::kLine3, K::kCylinder}));
      break;
    }
    case T::kCircularity:
      TPCAL_RETURN_IF_ERROR(feature({K::kCircle, K::kPitchCircle}));
      TPCAL_RETURN_IF_ERROR(no_datum());
      break;
    case T::kFlatness:
      TPCAL_RETURN_IF_ERROR(feature({K::kPlane}));
      TPCAL_RETURN_IF_ERROR(no_datum());
      break;
    case T::kStraightness:
      TPCAL_RETURN_IF_ERROR(feature({K::kLine2, K::kLine3}));
      TPCAL_RETURN_IF_ERROR(no_datum());
      break;
    case T::kPlaneDistance:
      TPCAL_RETURN_IF_ERROR(feature({K::kPlane}));
      TPCAL_RETURN_IF_ERROR(datum({K::kPlane}));
      if (!ch.nominal_distance_mm) return c.Error(ch.line, what + ": nominal_distance_mm is required");
      break;
    case T::kSize:
      TPCAL_RETURN_IF_ERROR(feature({K::kCircle, K::kCylinder, K::kSphere, K::kPitchCircle}));
      TPCAL_RETURN_IF_ERROR(no_datum());
      if (ch.nominal_radius_mm.has_value() == ch.nominal_diameter_mm.has_value())
        return c.Error(ch.line, what + ": give exactly one of nominal_radius_mm, nominal_diameter_mm");
      if (!(ch.nominal_radius_mm.value_or(1.0) > 0.0) || !(ch.nominal_diameter_mm.value_or(1.0) > 0.0))
        return c.Error(ch.line, what + ": nominal size must be positive");
      break;
    case T::kHolePattern: {
      auto f = feature({K::kPitchCircle});
      if (!f.ok()) return f.status();
      TPCAL_RETURN_IF_ERROR(no_datum());
      TPCAL_RETURN_IF_ERROR(plane_matches(*f));
      if (!ch.nominal_radius_mm || !(*ch.nominal_radius_mm > 0.0))
        return c.Error(ch.line, what + ": a positive nominal_radius_mm (pitch radius) is required");
      const bool listed = !ch.nominal_angles_deg.empty();
      const bool regular = ch.first_angle_deg.has_value() || ch.pitch_deg.has_value();
      if (listed == regular || (regular && !(ch.first_angle_deg && ch.pitch_deg)))
        return c.Error(ch.line, what + ": give either nominal_angles_deg or both first_angle_deg and pitch_deg");
      if (listed && ch.nominal_angles_deg.size() != (*f)->members.size())
        return c.Error(ch.line, what + ": nominal_angles_deg has " + std::to_string(ch.nominal_angles_deg.size()) +
                                    " angles for " + std::to_string((*f)->members.size()) + " members");
      break;
    }
  }
  const bool uses_datum = ch.type == T::kConcentricity || ch.type == T::kParallelism || ch.type == T::kSquareness ||
                          ch.type == T::kPlaneDistance;
  if (uses_datum && ch.datum == ch.feature)
    return c.Error(ch.line, what + ": feature and datum are the same feature");
  return Status::Ok();
}

}  // namespace

const char* FeatureKindName(FeatureKind k) { return NameOf(k, kKinds); }
const char* ProjectionName(Projection p) { return NameOf(p, kProjections); }
const char* FormCriterionName(FormCriterion c) { return NameOf(c, kCriteria); }
const char* CharacteristicTypeName(CharacteristicType t) { return NameOf(t, kTypes); }
std::optional<FeatureKind> ParseFeatureKind(std::string_view s) { return ParseByName(s, kKinds); }
std::optional<Projection> ParseProjection(std::string_view s) { return ParseByName(s, kProjections); }
std::optional<FormCriterion> ParseFormCriterion(std::string_view s) { return ParseByName(s, kCriteria); }
std::optional<CharacteristicType> ParseCharacteristicType(std::string_view s) { return ParseByName(s, kTypes); }

const char* DatumFrameTypeName(DatumFrameType t) {
  switch (t) {
    case DatumFrameType::kTurning: return "turning";
    case DatumFrameType::kThreeTwoOne: return "3-2-1";
    case DatumFrameType::kTargets: return "targets";
  }
  return "?";
}

std::size_t MinPoints(FeatureKind k) {
  switch (k) {
    case FeatureKind::kLine2: return 2;
    case FeatureKind::kLine3: return 2;
    case FeatureKind::kPlane: return 3;
    case FeatureKind::kCircle: return 3;
    case FeatureKind::kCylinder: return 5;
    case FeatureKind::kSphere: return 4;
    case FeatureKind::kCone: return 6;
    case FeatureKind::kPoint: return 1;
    case FeatureKind::kPitchCircle: return 3;
  }
  return 1;
}

const FeatureSpec* InspectionPlan::FindFeature(const std::string& name) const {
  for (const FeatureSpec& f : features)
    if (f.name == name) return &f;
  return nullptr;
}

std::optional<double> InspectionPlan::Nominal(const std::string& name) const {
  for (const PlanNominal& n : nominals)
    if (n.name == name) return n.value;
  return std::nullopt;
}

Status ValidatePlan(const InspectionPlan& plan) {
  const Checker c(plan);
  std::set<std::string> nominal_names;
  for (const PlanNominal& n : plan.nominals) {
    static const char* const kSuffixes[] = {"_mm", "_um", "_deg", "_rad", "_urad", "_count"};
    const bool has_unit = std::any_of(std::begin(kSuffixes), std::end(kSuffixes), [&](const char* suf) {
      const std::string_view sv(suf);
      return n.name.size() > sv.size() && std::string_view(n.name).substr(n.name.size() - sv.size()) == sv;
    });
    if (!has_unit)
      return c.Error(n.line, "nominal '" + n.name + "': the name must end with its unit (_mm, _um, _deg, _rad, _urad, _count)");
    if (!nominal_names.insert(n.name).second) return c.Error(n.line, "nominal '" + n.name + "' defined twice");
  }
  std::set<std::string> names;
  for (const FeatureSpec& f : plan.features) {
    if (f.name.empty()) return c.Error(f.line, "feature with an empty name");
    if (!names.insert(f.name).second) return c.Error(f.line, "feature '" + f.name + "' defined twice");
  }
  for (const FeatureSpec& f : plan.features) TPCAL_RETURN_IF_ERROR(ValidateFeature(plan, c, f));
  if (plan.datum_frame) TPCAL_RETURN_IF_ERROR(ValidateFrame(c, *plan.datum_frame));
  std::set<std::string> char_names;
  for (const CharacteristicSpec& ch : plan.characteristics) {
    if (ch.name.empty()) return c.Error(ch.line, "characteristic with an empty name");
    if (!char_names.insert(ch.name).second) return c.Error(ch.line, "characteristic '" + ch.name + "' defined twice");
    TPCAL_RETURN_IF_ERROR(ValidateCharacteristic(c, ch));
  }
  return Status::Ok();
}

}  // namespace tpcal::gdt
