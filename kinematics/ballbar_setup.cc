#include "kinematics/ballbar_setup.h"

#include <set>

#include "kinematics/internal/yaml_util.h"

namespace tpcal::kinematics {

namespace y = yaml_internal;

namespace {

// File-local names carry a Bbs prefix: a unity build merges this file with the other kinematics
// readers (artifacts_yaml.cc, machine_yaml.cc, ...), which have their own helpers.

constexpr const char* kBbsSchema = "tpcal.ballbar_setup/1";

Result<double> BbsNumber(const std::string& src, const std::vector<y::MapEntry>& entries, const YAML::Node& where,
                         const std::string& key, const std::string& what) {
  const y::MapEntry* e = y::Find(entries, key);
  if (!e) return y::Error(src, where, what + ": missing '" + key + "'");
  return y::Double(src, e->value, what + "." + key);
}

Status BbsHold(const std::string& src, const YAML::Node& node, const std::string& what, BallbarInstallation* inst) {
  Result<std::vector<y::MapEntry>> entries = y::Entries(src, node, what);
  TPCAL_RETURN_IF_ERROR(entries);
  for (const y::MapEntry& e : *entries) {
    const std::optional<Axis> a = AxisFromName(e.key);
    if (!a || !IsRotary(*a))
      return y::Error(src, e.key_node, what + ": key '" + EchoInput(e.key) + "': expected a rotary axis A, B or C");
    if (inst->kind != BallbarKind::kCircle && *a == inst->axis)
      return y::Error(src, e.key_node, what + ": " + e.key + " is the turned axis; it cannot be held");
    Result<double> v = y::Double(src, e.value, what + "." + e.key);
    TPCAL_RETURN_IF_ERROR(v);
    inst->hold_deg[*a] = *v;
  }
  return Status::Ok();
}

Status BbsKindAndAxis(const std::string& src, const std::vector<y::MapEntry>& entries, const YAML::Node& node,
                      const std::string& what, BallbarInstallation* inst) {
  const y::MapEntry* kind = y::Find(entries, "kind");
  if (!kind) return y::Error(src, node, what + ": missing 'kind' (radial, tangential, axial or circle)");
  Result<std::string> k = y::String(src, kind->value, what + ".kind");
  TPCAL_RETURN_IF_ERROR(k);
  const std::optional<BallbarKind> parsed = BallbarKindFromName(*k);
  if (!parsed)
    return y::Error(src, kind->value,
                    what + ".kind '" + EchoInput(*k) + "': expected radial, tangential, axial or circle");
  inst->kind = *parsed;
  const y::MapEntry* axis = y::Find(entries, "axis");
  if (!axis) return y::Error(src, node, what + ": missing 'axis' (A, B or C; for a circle XY, YZ or ZX)");
  Result<std::string> a = y::String(src, axis->value, what + ".axis");
  TPCAL_RETURN_IF_ERROR(a);
  if (inst->kind == BallbarKind::kCircle) {
    const std::optional<BallbarPlane> p = BallbarPlaneFromName(*a);
    if (!p) return y::Error(src, axis->value, what + ".axis '" + EchoInput(*a) + "': a circle needs a plane XY, YZ or ZX");
    inst->plane = *p;
    return Status::Ok();
  }
  const std::optional<Axis> r = AxisFromName(*a);
  if (!r || !IsRotary(*r))
    return y::Error(src, axis->value, what + ".axis '" + EchoInput(*a) + "': expected a rotary axis A, B or C");
  inst->axis = *r;
  return Status::Ok();
}

Result<BallbarInstallation> BbsInstallation(const std::string& src, const YAML::Node& node, const std::string& what) {
  Result<std::vector<y::MapEntry>> entries = y::Entries(src, node, what);
  TPCAL_RETURN_IF_ERROR(entries);
  TPCAL_RETURN_IF_ERROR(y::CheckKeys(src, *entries,
                                     {"name", "kind", "axis", "workpiece_ball_in_part_mm", "tool_ball_in_tool_mm",
                                      "nominal_length_mm", "sense", "hold_deg"},
                                     what));
  BallbarInstallation inst;
  const y::MapEntry* name = y::Find(*entries, "name");
  if (!name) return y::Error(src, node, what + ": missing 'name' (as in the ball-bar file's setup column)");
  Result<std::string> s = y::CsvName(src, name->value, what, "the ball-bar file");
  TPCAL_RETURN_IF_ERROR(s);
  inst.name = *s;
  TPCAL_RETURN_IF_ERROR(BbsKindAndAxis(src, *entries, node, what, &inst));
  Result<Eigen::Vector3d> w = y::Vector3At(src, *entries, node, "workpiece_ball_in_part_mm", what);
  TPCAL_RETURN_IF_ERROR(w);
  inst.workpiece_ball_in_part_mm = *w;
  Result<Eigen::Vector3d> t = y::Vector3At(src, *entries, node, "tool_ball_in_tool_mm", what);
  TPCAL_RETURN_IF_ERROR(t);
  inst.tool_ball_in_tool_mm = *t;
  Result<double> length = BbsNumber(src, *entries, node, "nominal_length_mm", what);
  TPCAL_RETURN_IF_ERROR(length);
  if (!(*length > 0.0))
    return y::Error(src, y::Find(*entries, "nominal_length_mm")->value, what + ".nominal_length_mm: expected > 0");
  inst.nominal_length_mm = *length;
  if (const y::MapEntry* e = y::Find(*entries, "sense")) {
    if (inst.kind == BallbarKind::kCircle)
      return y::Error(src, e->key_node, what + ".sense: not used by a circle (the path angle gives the direction)");
    Result<int> v = y::Int(src, e->value, what + ".sense");
    TPCAL_RETURN_IF_ERROR(v);
    if (*v != 1 && *v != -1) return y::Error(src, e->value, what + ".sense: expected +1 or -1");
    inst.sense = *v;
  }
  if (const y::MapEntry* e = y::Find(*entries, "hold_deg"))
    TPCAL_RETURN_IF_ERROR(BbsHold(src, e->value, what + ".hold_deg", &inst));
  return inst;
}

Result<BallbarSetup> BbsParse(const std::string& src, const YAML::Node& root) {
  if (root.IsNull())
    return Status(StatusCode::kParseError, "empty file: expected 'installations:' with a list of installations", src, 1);
  Result<std::vector<y::MapEntry>> entries = y::Entries(src, root, "ball-bar set-up file");
  TPCAL_RETURN_IF_ERROR(entries);
  TPCAL_RETURN_IF_ERROR(y::CheckKeys(src, *entries, {"schema", "installations"}, "ball-bar set-up file"));
  if (const y::MapEntry* e = y::Find(*entries, "schema")) {
    Result<std::string> s = y::String(src, e->value, "schema");
    TPCAL_RETURN_IF_ERROR(s);
    if (*s != kBbsSchema)
      return y::Error(src, e->value, "schema: expected " + std::string(kBbsSchema) + ", got " + EchoInput(*s));
  }
  const y::MapEntry* list = y::Find(*entries, "installations");
  if (!list) return y::Error(src, root, "ball-bar set-up file: missing 'installations' (a list)");
  if (!list->value.IsSequence()) return y::Error(src, list->value, "installations: expected a list of installations");
  if (list->value.size() == 0) return y::Error(src, list->key_node, "installations: no installations");
  BallbarSetup setup;
  std::set<std::string> names;
  for (std::size_t i = 0; i < list->value.size(); ++i) {
    const YAML::Node node = list->value[i];
    const std::string what = "installations[" + std::to_string(i) + "]";
    Result<BallbarInstallation> inst = BbsInstallation(src, node, what);
    TPCAL_RETURN_IF_ERROR(inst);
    if (!names.insert(inst->name).second)
      return y::Error(src, node, what + ": name '" + EchoInput(inst->name) + "' repeated");
    setup.installations.push_back(std::move(*inst));
  }
  return setup;
}

}  // namespace

const char* BallbarKindName(BallbarKind k) {
  switch (k) {
    case BallbarKind::kRadial: return "radial";
    case BallbarKind::kTangential: return "tangential";
    case BallbarKind::kAxial: return "axial";
    case BallbarKind::kCircle: return "circle";
  }
  return "?";
}

std::optional<BallbarKind> BallbarKindFromName(std::string_view name) {
  for (BallbarKind k : {BallbarKind::kRadial, BallbarKind::kTangential, BallbarKind::kAxial, BallbarKind::kCircle})
    if (name == BallbarKindName(k)) return k;
  return std::nullopt;
}

const char* BallbarPlaneName(BallbarPlane p) {
  switch (p) {
    case BallbarPlane::kXY: return "XY";
    case BallbarPlane::kYZ: return "YZ";
    case BallbarPlane::kZX: return "ZX";
  }
  return "?";
}

std::optional<BallbarPlane> BallbarPlaneFromName(std::string_view name) {
  for (BallbarPlane p : {BallbarPlane::kXY, BallbarPlane::kYZ, BallbarPlane::kZX})
    if (name == BallbarPlaneName(p)) return p;
  return std::nullopt;
}

const BallbarInstallation* BallbarSetup::Find(std::string_view name) const {
  for (const BallbarInstallation& i : installations)
    if (i.name == name) return &i;
  return nullptr;
}

Result<BallbarSetup> ParseBallbarSetup(std::string_view text, const std::string& source) {
  Result<YAML::Node> root = y::Parse(std::string(text), source);
  TPCAL_RETURN_IF_ERROR(root);
  try {
    return BbsParse(source, *root);
  } catch (const YAML::Exception& e) {
    return Status(StatusCode::kParseError, "YAML: " + EchoInput(e.what(), 2 * kMaxEchoBytes), source,
                  e.mark.line >= 0 ? static_cast<std::size_t>(e.mark.line) + 1 : 0);
  }
}

Result<BallbarSetup> LoadBallbarSetup(const std::string& path) {
  Result<std::string> text = y::ReadFile(path);
  TPCAL_RETURN_IF_ERROR(text);
  return ParseBallbarSetup(*text, path);
}

std::string FormatBallbarSetup(const BallbarSetup& setup) {
  std::string out = std::string("schema: ") + kBbsSchema + "\ninstallations:\n";
  for (const BallbarInstallation& i : setup.installations) {
    const bool circle = i.kind == BallbarKind::kCircle;
    out += "  - name: " + y::Quoted(i.name) + "\n";
    out += std::string("    kind: ") + BallbarKindName(i.kind) + "\n";
    out += std::string("    axis: ") + (circle ? BallbarPlaneName(i.plane) : std::string(1, AxisLetter(i.axis))) + "\n";
    out += "    workpiece_ball_in_part_mm: " + y::FormatVector3(i.workpiece_ball_in_part_mm) + "\n";
    out += "    tool_ball_in_tool_mm: " + y::FormatVector3(i.tool_ball_in_tool_mm) + "\n";
    out += "    nominal_length_mm: " + y::FormatDouble(i.nominal_length_mm) + "\n";
    if (!circle) out += "    sense: " + std::to_string(i.sense) + "\n";
    if (!i.hold_deg.empty()) {
      std::string list;
      for (const auto& [a, v] : i.hold_deg)
        list += (list.empty() ? "" : ", ") + std::string(1, AxisLetter(a)) + ": " + y::FormatDouble(v);
      out += "    hold_deg: {" + list + "}\n";
    }
  }
  return out;
}

BallbarSetup Seed003CTableSetup(Axis hold) {
  struct Placed { const char* name; BallbarKind kind; double x_mm, z_mm; };
  BallbarSetup setup;
  for (const Placed& p : {Placed{"C_radial_L1H1", BallbarKind::kRadial, 100, 50},
                          {"C_tangential_L1H1", BallbarKind::kTangential, 100, 50},
                          {"C_axial_H1", BallbarKind::kAxial, 0, 50},
                          {"C_radial_L2H1", BallbarKind::kRadial, 150, 50},
                          {"C_tangential_L2H1", BallbarKind::kTangential, 150, 50},
                          {"C_radial_L1H3", BallbarKind::kRadial, 100, 100},
                          {"C_tangential_L1H3", BallbarKind::kTangential, 100, 100}}) {
    BallbarInstallation i;
    i.name = p.name, i.kind = p.kind, i.axis = Axis::kC;
    i.workpiece_ball_in_part_mm = Eigen::Vector3d(p.x_mm, 0.0, p.z_mm);
    i.nominal_length_mm = 150.0, i.sense = +1;
    i.hold_deg[hold] = 0.0;
    setup.installations.push_back(std::move(i));
  }
  return setup;
}

}  // namespace tpcal::kinematics
