#include "gdt/plan_yaml.h"

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <initializer_list>
#include <set>
#include <vector>

#include "core/input_echo.h"
#include "core/text_file.h"

namespace tpcal::gdt {
namespace {

constexpr const char* kSchema = "tpcal.inspection_plan/1";
// Names (features, characteristics, nominals, references) and free text: they reach messages
// and JSON, so they are printable UTF-8 of bounded length.
constexpr std::size_t kMaxNameBytes = 128;
constexpr std::size_t kMaxTextBytes = 4096;

class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  static std::size_t Line(const YAML::Node& n) {
    const YAML::Mark m = n.Mark();
    return m.line < 0 ? 0 : static_cast<std::size_t>(m.line) + 1;
  }

  Status Error(const YAML::Node& at, const std::string& msg) const {
    return Status(StatusCode::kParseError, msg, source_, Line(at));
  }

  // `node` must be a map whose keys are all in `allowed` and appear once.
  Status CheckMap(const YAML::Node& node, const std::string& what, const std::set<std::string>& allowed) const {
    if (!node.IsMap()) return Error(node, what + ": expected a map of key: value");
    std::set<std::string> seen;
    for (const auto& kv : node) {
      if (!kv.first.IsScalar()) return Error(kv.first, what + ": keys must be plain names");
      const std::string key = kv.first.Scalar();
      if (!allowed.contains(key)) {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
        return Error(kv.first, what + ": unknown key '" + EchoInput(key) + "' (allowed: " + list + ")");
      }
      if (!seen.insert(key).second) return Error(kv.first, what + ": key '" + EchoInput(key) + "' given twice");
    }
    return Status::Ok();
  }

  Result<std::string> String(const YAML::Node& n, const std::string& what,
                             std::size_t max_bytes = kMaxNameBytes) const {
    if (!n.IsScalar()) return Error(n, what + ": expected a text value");
    const std::string& s = n.Scalar();
    const bool text = max_bytes > kMaxNameBytes;  // free text may hold tabs and line breaks; a name is one printable line
    bool printable = FirstInvalidUtf8(s) == std::string_view::npos;
    for (char c : s) {
      const bool layout = text && (c == '\n' || c == '\t');
      printable = printable && !((static_cast<unsigned char>(c) < 0x20 && !layout) || c == 0x7F);
    }
    if (!printable || s.size() > max_bytes)
      return Error(n, what + ": '" + EchoInput(s) + "': expected printable UTF-8 text of at most " +
                          std::to_string(max_bytes) + " bytes");
    return s;
  }

  Result<double> Number(const YAML::Node& n, const std::string& what) const {
    if (!n.IsScalar()) return Error(n, what + ": expected a number");
    double v = 0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      return Error(n, what + ": expected a number, got '" + EchoInput(n.Scalar()) + "'");
    }
    if (!std::isfinite(v)) return Error(n, what + ": expected a finite number");
    return v;
  }

  Result<std::vector<double>> Numbers(const YAML::Node& n, const std::string& what, std::size_t size = 0) const {
    if (!n.IsSequence()) return Error(n, what + ": expected a list of numbers [a, b, ...]");
    if (size != 0 && n.size() != size)
      return Error(n, what + ": expected " + std::to_string(size) + " numbers, got " + std::to_string(n.size()));
    std::vector<double> out;
    for (const auto& e : n) {
      auto v = Number(e, what);
      if (!v.ok()) return v.status();
      out.push_back(*v);
    }
    return out;
  }

  Result<std::vector<std::string>> Strings(const YAML::Node& n, const std::string& what) const {
    if (!n.IsSequence()) return Error(n, what + ": expected a list of names [a, b, ...]");
    std::vector<std::string> out;
    for (const auto& e : n) {
      auto v = String(e, what);
      if (!v.ok()) return v.status();
      out.push_back(*v);
    }
    return out;
  }

  template <typename E>
  Result<E> Enum(const YAML::Node& n, const std::string& what, std::optional<E> (*parse)(std::string_view),
                 const char* expected) const {
    auto s = String(n, what);
    if (!s.ok()) return s.status();
    auto e = parse(*s);
    if (!e) return Error(n, what + ": unknown value '" + EchoInput(*s) + "', expected one of " + expected);
    return *e;
  }

  const std::string& source() const { return source_; }

 private:
  std::string source_;
};

#define TPCAL_ASSIGN_OR_RETURN(lhs, expr) \
  do {                                    \
    auto r_ = (expr);                     \
    if (!r_.ok()) return r_.status();     \
    lhs = std::move(*r_);                 \
  } while (0)

Result<AxisSense> ParseSense(const Reader& rd, const YAML::Node& n, const std::string& what) {
  AxisSense s;
  if (n.IsScalar()) {
    const std::string v = n.Scalar();
    if (v == "point_normals") {
      s.rule = AxisSense::Rule::kPointNormals;
    } else if (v == "point_order") {
      s.rule = AxisSense::Rule::kPointOrder;
    } else {
      return rd.Error(n, what + ": expected point_normals, point_order, {away_from: FEATURE} or {toward: FEATURE}");
    }
    return s;
  }
  TPCAL_RETURN_IF_ERROR(rd.CheckMap(n, what, {"away_from", "toward"}));
  if (n.size() != 1) return rd.Error(n, what + ": give one of away_from, toward");
  const auto kv = *n.begin();
  s.rule = kv.first.Scalar() == "away_from" ? AxisSense::Rule::kAwayFrom : AxisSense::Rule::kToward;
  TPCAL_ASSIGN_OR_RETURN(s.feature, rd.String(kv.second, what + " " + EchoInput(kv.first.Scalar())));
  return s;
}

Result<DatumFrameSpec> ParseFrame(const Reader& rd, const YAML::Node& n) {
  const std::string what = "datum_frame";
  TPCAL_RETURN_IF_ERROR(rd.CheckMap(n, what,
                                    {"type", "primary", "center", "x_toward", "y_toward", "toward_first_point",
                                     "secondary", "tertiary", "z_sense", "x_sense"}));
  DatumFrameSpec d;
  d.line = Reader::Line(n);
  if (!n["type"]) return rd.Error(n, what + ": missing key 'type' (turning, 3-2-1 or targets)");
  std::string type;
  TPCAL_ASSIGN_OR_RETURN(type, rd.String(n["type"], what + " type"));
  if (type == "turning") {
    d.type = DatumFrameType::kTurning;
  } else if (type == "3-2-1") {
    d.type = DatumFrameType::kThreeTwoOne;
  } else if (type == "targets") {
    d.type = DatumFrameType::kTargets;
  } else {
    return rd.Error(n["type"], what + " type: unknown value '" + EchoInput(type) + "', expected turning, 3-2-1 or targets");
  }
  // Keys each type requires, and keys that belong to the other types only.
  using Keys = std::vector<std::pair<const char*, std::string*>>;
  Keys required;
  std::vector<const char*> foreign;
  switch (d.type) {
    case DatumFrameType::kTurning:
      required = Keys{{"primary", &d.primary}, {"center", &d.center}, {"x_toward", &d.x_toward}};
      foreign = {"secondary", "tertiary", "x_sense", "y_toward", "toward_first_point"};
      break;
    case DatumFrameType::kThreeTwoOne:
      required = Keys{{"primary", &d.primary}, {"secondary", &d.secondary}, {"tertiary", &d.tertiary}};
      foreign = {"center", "x_toward", "y_toward", "toward_first_point"};
      break;
    case DatumFrameType::kTargets:
      required = Keys{{"primary", &d.primary}, {"center", &d.center}};
      foreign = {"secondary", "tertiary", "x_sense"};
      break;
  }
  for (const auto& [key, dst] : required) {
    if (!n[key]) return rd.Error(n, what + " (" + type + "): missing key '" + key + "'");
    TPCAL_ASSIGN_OR_RETURN(*dst, rd.String(n[key], what + " " + key));
  }
  for (const char* key : foreign) {
    if (n[key]) return rd.Error(n[key], what + ": key '" + key + "' does not apply to a " + type + " frame");
  }
  if (d.type == DatumFrameType::kTargets) {
    // Exactly one direction target (ValidateFrame checks the features it names).
    if (n["x_toward"].IsDefined() == n["y_toward"].IsDefined())
      return rd.Error(n, what + " (targets): give exactly one of x_toward and y_toward");
    if (n["x_toward"]) TPCAL_ASSIGN_OR_RETURN(d.x_toward, rd.String(n["x_toward"], what + " x_toward"));
    if (n["y_toward"]) TPCAL_ASSIGN_OR_RETURN(d.y_toward, rd.String(n["y_toward"], what + " y_toward"));
    if (n["toward_first_point"]) {
      const YAML::Node& b = n["toward_first_point"];
      if (!b.IsScalar() || (b.Scalar() != "true" && b.Scalar() != "false"))
        return rd.Error(b, what + " toward_first_point: expected true or false");
      d.toward_first_point = b.Scalar() == "true";
    }
  }
  if (!n["z_sense"])
    return rd.Error(n, what + ": missing key 'z_sense' (point_normals, {away_from: FEATURE} or {toward: FEATURE}); "
                              "the CMM frame never decides the part's +Z");
  TPCAL_ASSIGN_OR_RETURN(d.z_sense, ParseSense(rd, n["z_sense"], what + " z_sense"));
  if (n["x_sense"]) TPCAL_ASSIGN_OR_RETURN(d.x_sense, ParseSense(rd, n["x_sense"], what + " x_sense"));
  return d;
}

Result<FeatureSpec> ParseFeature(const Reader& rd, const YAML::Node& key, const YAML::Node& n, bool has_frame) {
  FeatureSpec f;
  TPCAL_ASSIGN_OR_RETURN(f.name, rd.String(key, "feature name"));
  const std::string what = "feature '" + f.name + "'";
  f.line = Reader::Line(key);
  TPCAL_RETURN_IF_ERROR(rd.CheckMap(n, what, {"kind", "projection", "form_criterion", "nominal_direction", "members"}));
  if (!n["kind"]) return rd.Error(n, what + ": missing key 'kind'");
  TPCAL_ASSIGN_OR_RETURN(f.kind, rd.Enum<FeatureKind>(n["kind"], what + " kind", ParseFeatureKind,
                                                      "line2, line3, plane, circle, cylinder, sphere, cone, point, "
                                                      "pitch_circle"));
  const bool planar = f.kind == FeatureKind::kLine2 || f.kind == FeatureKind::kPitchCircle;
  if (planar || (f.kind == FeatureKind::kCircle && has_frame)) f.projection = Projection::kDatumXY;
  if (n["projection"])
    TPCAL_ASSIGN_OR_RETURN(f.projection, rd.Enum<Projection>(n["projection"], what + " projection", ParseProjection,
                                                             "none, datum_xy, datum_yz, datum_zx"));
  if (n["form_criterion"])
    TPCAL_ASSIGN_OR_RETURN(f.form_criterion, rd.Enum<FormCriterion>(n["form_criterion"], what + " form_criterion",
                                                                    ParseFormCriterion, "ls, mz"));
  if (n["nominal_direction"]) {
    std::vector<double> v;
    TPCAL_ASSIGN_OR_RETURN(v, rd.Numbers(n["nominal_direction"], what + " nominal_direction", 3));
    f.nominal_direction = Eigen::Vector3d(v[0], v[1], v[2]);
  }
  if (n["members"]) TPCAL_ASSIGN_OR_RETURN(f.members, rd.Strings(n["members"], what + " members"));
  return f;
}

// The keys a characteristic of each type accepts: a key of another type is an error too.
std::set<std::string> KeysFor(CharacteristicType t) {
  std::set<std::string> keys = {"name", "type", "feature", "symbol", "description"};
  auto add = [&](std::initializer_list<const char*> more) { keys.insert(more.begin(), more.end()); };
  switch (t) {
    case CharacteristicType::kConcentricity: add({"datum", "plane"}); break;
    case CharacteristicType::kParallelism:
    case CharacteristicType::kSquareness: add({"datum"}); break;
    case CharacteristicType::kCircularity:
    case CharacteristicType::kFlatness:
    case CharacteristicType::kStraightness: add({"criterion"}); break;
    case CharacteristicType::kPosition:
      add({"plane", "nominal_xy_mm", "nominal_xyz_mm", "nominal_radius_mm", "nominal_angle_deg"});
      break;
    case CharacteristicType::kPlaneDistance: add({"datum", "nominal_distance_mm"}); break;
    case CharacteristicType::kSize: add({"nominal_radius_mm", "nominal_diameter_mm"}); break;
    case CharacteristicType::kHolePattern:
      add({"plane", "nominal_radius_mm", "first_angle_deg", "pitch_deg", "nominal_angles_deg"});
      break;
  }
  return keys;
}

Result<CharacteristicSpec> ParseCharacteristic(const Reader& rd, const YAML::Node& n) {
  CharacteristicSpec c;
  c.line = Reader::Line(n);
  if (!n.IsMap()) return rd.Error(n, "characteristic: expected a map of key: value");
  if (!n["name"]) return rd.Error(n, "characteristic: missing key 'name'");
  TPCAL_ASSIGN_OR_RETURN(c.name, rd.String(n["name"], "characteristic name"));
  const std::string what = "characteristic '" + c.name + "'";
  if (!n["type"]) return rd.Error(n, what + ": missing key 'type'");
  TPCAL_ASSIGN_OR_RETURN(c.type, rd.Enum<CharacteristicType>(n["type"], what + " type", ParseCharacteristicType,
                                                             "concentricity, parallelism, squareness, circularity, "
                                                             "flatness, straightness, position, plane_distance, size, "
                                                             "hole_pattern"));
  TPCAL_RETURN_IF_ERROR(rd.CheckMap(n, what + " (" + CharacteristicTypeName(c.type) + ")", KeysFor(c.type)));
  if (!n["feature"]) return rd.Error(n, what + ": missing key 'feature'");
  TPCAL_ASSIGN_OR_RETURN(c.feature, rd.String(n["feature"], what + " feature"));
  if (n["datum"]) TPCAL_ASSIGN_OR_RETURN(c.datum, rd.String(n["datum"], what + " datum"));
  if (n["symbol"]) TPCAL_ASSIGN_OR_RETURN(c.symbol, rd.String(n["symbol"], what + " symbol"));
  if (n["description"]) TPCAL_ASSIGN_OR_RETURN(c.description, rd.String(n["description"], what + " description", kMaxTextBytes));
  if (n["plane"])
    TPCAL_ASSIGN_OR_RETURN(c.plane, rd.Enum<Projection>(n["plane"], what + " plane", ParseProjection,
                                                        "datum_xy, datum_yz, datum_zx"));
  if (n["criterion"]) {
    FormCriterion crit{};
    TPCAL_ASSIGN_OR_RETURN(crit, rd.Enum<FormCriterion>(n["criterion"], what + " criterion", ParseFormCriterion, "ls, mz"));
    c.criterion = crit;
  }
  const std::vector<std::pair<const char*, std::optional<double>*>> scalars = {
      {"nominal_radius_mm", &c.nominal_radius_mm}, {"nominal_diameter_mm", &c.nominal_diameter_mm},
      {"nominal_distance_mm", &c.nominal_distance_mm}, {"nominal_angle_deg", &c.nominal_angle_deg},
      {"first_angle_deg", &c.first_angle_deg}, {"pitch_deg", &c.pitch_deg}};
  for (const auto& [key, dst] : scalars) {
    if (!n[key]) continue;
    double v = 0;
    TPCAL_ASSIGN_OR_RETURN(v, rd.Number(n[key], what + " " + key));
    *dst = v;
  }
  if (n["nominal_xy_mm"]) {
    std::vector<double> v;
    TPCAL_ASSIGN_OR_RETURN(v, rd.Numbers(n["nominal_xy_mm"], what + " nominal_xy_mm", 2));
    c.nominal_xy_mm = Eigen::Vector2d(v[0], v[1]);
  }
  if (n["nominal_xyz_mm"]) {
    std::vector<double> v;
    TPCAL_ASSIGN_OR_RETURN(v, rd.Numbers(n["nominal_xyz_mm"], what + " nominal_xyz_mm", 3));
    c.nominal_xyz_mm = Eigen::Vector3d(v[0], v[1], v[2]);
  }
  if (n["nominal_angles_deg"])
    TPCAL_ASSIGN_OR_RETURN(c.nominal_angles_deg, rd.Numbers(n["nominal_angles_deg"], what + " nominal_angles_deg"));
  return c;
}

Result<InspectionPlan> ParseDocument(const Reader& rd, const YAML::Node& root) {
  InspectionPlan plan;
  plan.source = rd.source();
  if (!root || root.IsNull()) return Status(StatusCode::kParseError, "empty plan", rd.source());
  TPCAL_RETURN_IF_ERROR(
      rd.CheckMap(root, "plan",
                  {"schema", "name", "description", "nominals", "datum_frame", "features", "characteristics"}));
  if (!root["schema"]) return rd.Error(root, std::string("plan: missing key 'schema' (") + kSchema + ")");
  std::string schema;
  TPCAL_ASSIGN_OR_RETURN(schema, rd.String(root["schema"], "plan schema"));
  if (schema != kSchema)
    return rd.Error(root["schema"], "plan schema: '" + EchoInput(schema) + "' is not supported, expected " + kSchema);
  if (root["name"]) TPCAL_ASSIGN_OR_RETURN(plan.name, rd.String(root["name"], "plan name"));
  if (root["description"]) TPCAL_RETURN_IF_ERROR(rd.String(root["description"], "plan description", kMaxTextBytes));
  if (root["nominals"]) {
    const YAML::Node nominals = root["nominals"];
    if (!nominals.IsMap()) return rd.Error(nominals, "nominals: expected a map of name_unit: number");
    for (const auto& kv : nominals) {
      PlanNominal n;
      TPCAL_ASSIGN_OR_RETURN(n.name, rd.String(kv.first, "nominal name"));
      TPCAL_ASSIGN_OR_RETURN(n.value, rd.Number(kv.second, "nominal '" + n.name + "'"));
      n.line = Reader::Line(kv.first);
      plan.nominals.push_back(std::move(n));
    }
  }
  if (root["datum_frame"]) {
    DatumFrameSpec d;
    TPCAL_ASSIGN_OR_RETURN(d, ParseFrame(rd, root["datum_frame"]));
    plan.datum_frame = d;
  }
  if (!root["features"]) return rd.Error(root, "plan: missing key 'features'");
  const YAML::Node features = root["features"];
  if (!features.IsMap() || features.size() == 0)
    return rd.Error(features, "features: expected a map of FEATURE: {kind: ...}");
  std::set<std::string> seen;
  for (const auto& kv : features) {
    FeatureSpec f;
    TPCAL_ASSIGN_OR_RETURN(f, ParseFeature(rd, kv.first, kv.second, plan.datum_frame.has_value()));
    if (!seen.insert(f.name).second) return rd.Error(kv.first, "feature '" + f.name + "' defined twice");
    plan.features.push_back(std::move(f));
  }
  if (root["characteristics"]) {
    const YAML::Node chars = root["characteristics"];
    if (!chars.IsSequence()) return rd.Error(chars, "characteristics: expected a list of - {name: ..., type: ...}");
    for (const auto& c : chars) {
      CharacteristicSpec spec;
      TPCAL_ASSIGN_OR_RETURN(spec, ParseCharacteristic(rd, c));
      plan.characteristics.push_back(std::move(spec));
    }
  }
  TPCAL_RETURN_IF_ERROR(ValidatePlan(plan));
  return plan;
}

#undef TPCAL_ASSIGN_OR_RETURN

}  // namespace

Result<InspectionPlan> ParseInspectionPlan(std::string_view text, const std::string& source) {
  const Reader rd(source);
  try {
    const YAML::Node root = YAML::Load(std::string(text));
    return ParseDocument(rd, root);
  } catch (const YAML::DeepRecursion& e) {
    return Status(StatusCode::kParseError, "YAML nested " + std::to_string(e.depth()) + " levels deep; expected a configuration, not nested lists or maps", source, static_cast<std::size_t>(e.mark.line) + 1);
  } catch (const YAML::Exception& e) {
    const std::size_t line = e.mark.line < 0 ? 0 : static_cast<std::size_t>(e.mark.line) + 1;
    return Status(StatusCode::kParseError, "YAML: " + EchoInput(e.msg, 2 * kMaxEchoBytes), source, line);
  }
}

Result<InspectionPlan> LoadInspectionPlan(const std::string& path) {
  Result<std::string> text = ReadTextFile(path, "cannot open inspection plan");
  if (!text.ok()) return text.status();
  return ParseInspectionPlan(*text, path);
}

}  // namespace tpcal::gdt
