#include "kinematics/machine_yaml.h"

#include <cstdio>
#include <set>

#include "core/units.h"
#include "kinematics/internal/yaml_util.h"

namespace tpcal::kinematics {

namespace y = yaml_internal;

namespace {

constexpr const char* kMachineSchema = "tpcal.machine/1";

Result<std::vector<Axis>> AxisList(const std::string& src, const YAML::Node& n,
                                   const std::string& what) {
  if (!n.IsSequence()) return y::Error(src, n, what + ": expected a list of axis letters, e.g. [A, C]");
  std::vector<Axis> out;
  for (std::size_t i = 0; i < n.size(); ++i) {
    Result<std::string> s = y::String(src, n[i], what);
    TPCAL_RETURN_IF_ERROR(s);
    const std::optional<Axis> a = AxisFromName(*s);
    if (!a) return y::Error(src, n[i], what + ": '" + EchoInput(*s) + "' is not an axis (X, Y, Z, A, B or C)");
    out.push_back(*a);
  }
  return out;
}

Status ParseAxis(const std::string& src, const YAML::Node& node, MachineModel* m, int link) {
  AxisLink& l = m->links[link];
  const std::string what = std::string("axes.") + AxisLetter(l.axis);
  Result<std::vector<y::MapEntry>> entries = y::Entries(src, node, what);
  TPCAL_RETURN_IF_ERROR(entries);
  const bool rotary = IsRotary(l.axis);
  const std::set<std::string> allowed =
      rotary ? std::set<std::string>{"min_deg", "max_deg", "continuous", "pivot_mm"}
             : std::set<std::string>{"min_mm", "max_mm", "pivot_mm"};
  TPCAL_RETURN_IF_ERROR(y::CheckKeys(src, *entries, allowed, what));
  const double scale = rotary ? kPi / 180.0 : 1.0;
  const std::string lo = rotary ? "min_deg" : "min_mm", hi = rotary ? "max_deg" : "max_mm";
  if (const y::MapEntry* e = y::Find(*entries, lo)) {
    Result<double> v = y::Double(src, e->value, what + "." + lo);
    TPCAL_RETURN_IF_ERROR(v);
    l.min_position = *v * scale;
  }
  if (const y::MapEntry* e = y::Find(*entries, hi)) {
    Result<double> v = y::Double(src, e->value, what + "." + hi);
    TPCAL_RETURN_IF_ERROR(v);
    l.max_position = *v * scale;
  }
  if (const y::MapEntry* e = y::Find(*entries, "continuous")) {
    Result<bool> v = y::Bool(src, e->value, what + ".continuous");
    TPCAL_RETURN_IF_ERROR(v);
    l.continuous = *v;
    if (l.continuous && (y::Find(*entries, lo) || y::Find(*entries, hi))) {
      return y::Error(src, e->key_node, what + ": a continuous axis has no min_deg / max_deg");
    }
  } else {
    l.continuous = false;
  }
  if (const y::MapEntry* e = y::Find(*entries, "pivot_mm")) {
    Result<Eigen::Vector3d> v = y::Vector3(src, e->value, what + ".pivot_mm");
    TPCAL_RETURN_IF_ERROR(v);
    l.pivot_mm = *v;
  } else if (m->type == MachineType::kBheadCtable && l.axis == Axis::kB) {
    return y::Error(src, node, what + ": a swinging head needs pivot_mm (pivot relative to the tool tip at B = 0)");
  } else {
    l.pivot_mm.setZero();
  }
  if (!(l.min_position <= l.max_position)) {
    return y::Error(src, node, what + ": minimum exceeds maximum");
  }
  return Status::Ok();
}

Result<MachineModel> Parse(const std::string& src, const YAML::Node& root) {
  Result<std::vector<y::MapEntry>> entries = y::Entries(src, root, "machine file");
  TPCAL_RETURN_IF_ERROR(entries);
  TPCAL_RETURN_IF_ERROR(y::CheckKeys(
      src, *entries, {"schema", "name", "type", "workpiece_chain", "tool_chain", "axes"}, "machine file"));
  if (const y::MapEntry* e = y::Find(*entries, "schema")) {
    Result<std::string> s = y::String(src, e->value, "schema");
    TPCAL_RETURN_IF_ERROR(s);
    if (*s != kMachineSchema) return y::Error(src, e->value, "schema: expected " + std::string(kMachineSchema) + ", got " + EchoInput(*s));
  }
  const y::MapEntry* type_entry = y::Find(*entries, "type");
  if (!type_entry) return y::Error(src, root, "machine file: missing 'type' (ac_table, bc_table, bhead_ctable or xyz)");
  Result<std::string> type_name = y::String(src, type_entry->value, "type");
  TPCAL_RETURN_IF_ERROR(type_name);
  const std::optional<MachineType> type = MachineTypeFromName(*type_name);
  if (!type) {
    return y::Error(src, type_entry->value,
                    "type: unknown machine type '" + EchoInput(*type_name) + "' (ac_table, bc_table, bhead_ctable or xyz)");
  }
  MachineLayout layout;
  const y::MapEntry* wc = y::Find(*entries, "workpiece_chain");
  const y::MapEntry* tc = y::Find(*entries, "tool_chain");
  if ((wc == nullptr) != (tc == nullptr)) {
    return y::Error(src, (wc ? wc : tc)->key_node, "give both workpiece_chain and tool_chain, or neither");
  }
  if (wc) {
    Result<std::vector<Axis>> w = AxisList(src, wc->value, "workpiece_chain");
    TPCAL_RETURN_IF_ERROR(w);
    Result<std::vector<Axis>> t = AxisList(src, tc->value, "tool_chain");
    TPCAL_RETURN_IF_ERROR(t);
    layout.workpiece_chain = *w;
    layout.tool_chain = *t;
  }
  Result<MachineModel> made = MakeMachine(*type, layout);
  if (!made.ok()) {
    return Status(StatusCode::kParseError, made.status().message(), src,
                  y::Line(wc ? wc->key_node : root));
  }
  MachineModel m = *made;
  if (const y::MapEntry* e = y::Find(*entries, "name")) {
    Result<std::string> s = y::String(src, e->value, "name");
    TPCAL_RETURN_IF_ERROR(s);
    m.name = *s;
  }
  const y::MapEntry* axes = y::Find(*entries, "axes");
  if (!axes) return y::Error(src, root, "machine file: missing 'axes' (strokes and pivots of every axis)");
  Result<std::vector<y::MapEntry>> axis_entries = y::Entries(src, axes->value, "axes");
  TPCAL_RETURN_IF_ERROR(axis_entries);
  std::set<Axis> given;
  for (const y::MapEntry& e : *axis_entries) {
    const std::optional<Axis> a = AxisFromName(e.key);
    if (!a || !m.HasAxis(*a)) {
      return y::Error(src, e.key_node,
                      "axes: '" + e.key + "' is not an axis of this " + MachineTypeName(m.type) + " chain");
    }
    TPCAL_RETURN_IF_ERROR(ParseAxis(src, e.value, &m, m.LinkIndex(*a)));
    given.insert(*a);
  }
  for (const AxisLink& l : m.links) {
    if (!given.count(l.axis)) {
      return y::Error(src, axes->value, std::string("axes: missing axis ") + AxisLetter(l.axis));
    }
  }
  Status s = m.Validate();
  if (!s.ok()) return Status(StatusCode::kParseError, s.message(), src, y::Line(root));
  return m;
}

}  // namespace

Result<MachineModel> ParseMachineModel(const std::string& yaml_text, const std::string& source) {
  Result<YAML::Node> root = y::Parse(yaml_text, source);
  TPCAL_RETURN_IF_ERROR(root);
  try {
    return Parse(source, *root);
  } catch (const YAML::Exception& e) {
    return Status(StatusCode::kParseError, std::string("YAML: ") + e.what(), source,
                  e.mark.line >= 0 ? static_cast<std::size_t>(e.mark.line) + 1 : 0);
  }
}

Result<MachineModel> LoadMachineModel(const std::string& path) {
  Result<std::string> text = y::ReadFile(path);
  TPCAL_RETURN_IF_ERROR(text);
  return ParseMachineModel(*text, path);
}

std::string FormatMachineModel(const MachineModel& m) {
  std::string out;
  char buf[256];
  out += "schema: tpcal.machine/1\n";
  out += "name: \"" + m.name + "\"\n";
  out += std::string("type: ") + MachineTypeName(m.type) + "\n";
  auto chain = [&](Branch b) {
    std::string s = "[";
    bool first = true;
    for (const AxisLink& l : m.links) {
      if (l.branch != b) continue;
      if (!first) s += ", ";
      s += AxisLetter(l.axis);
      first = false;
    }
    return s + "]";
  };
  out += "workpiece_chain: " + chain(Branch::kWorkpiece) + "\n";
  out += "tool_chain: " + chain(Branch::kTool) + "\n";
  out += "axes:\n";
  for (const AxisLink& l : m.links) {
    const bool rot = IsRotary(l.axis);
    const double k = rot ? 180.0 / kPi : 1.0;
    std::string fields;
    if (rot && l.continuous) {
      fields = "continuous: true";
    } else {
      std::snprintf(buf, sizeof(buf), "min_%s: %.17g, max_%s: %.17g", rot ? "deg" : "mm",
                    l.min_position * k, rot ? "deg" : "mm", l.max_position * k);
      fields = buf;
    }
    std::snprintf(buf, sizeof(buf), ", pivot_mm: [%.17g, %.17g, %.17g]", l.pivot_mm.x(),
                  l.pivot_mm.y(), l.pivot_mm.z());
    out += std::string("  ") + AxisLetter(l.axis) + ": {" + fields + buf + "}\n";
  }
  return out;
}

}  // namespace tpcal::kinematics
