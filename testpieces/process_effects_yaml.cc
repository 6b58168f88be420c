#include "testpieces/process_effects_yaml.h"

#include <cstdio>
#include <utility>
#include <vector>

#include "core/input_echo.h"
#include "kinematics/internal/yaml_util.h"

namespace tpcal::testpieces {
namespace {

namespace y = kinematics::yaml_internal;

constexpr const char* kProcessSchema = "tpcal.process/1";

// Reads the keys of one section into doubles (and the compliance vector) of the model.
Status ReadNumbers(const std::string& source, const YAML::Node& node, const std::string& section,
                   const std::vector<std::pair<std::string, double*>>& numbers, Eigen::Vector3d* vector3,
                   const std::string& vector3_key) {
  if (node.IsNull()) return {};
  auto entries = y::Entries(source, node, section);
  TPCAL_RETURN_IF_ERROR(entries);
  std::set<std::string> allowed;
  for (const auto& [key, _] : numbers) allowed.insert(key);
  if (vector3 != nullptr) allowed.insert(vector3_key);
  TPCAL_RETURN_IF_ERROR(y::CheckKeys(source, *entries, allowed, section));
  for (const auto& [key, target] : numbers) {
    if (const y::MapEntry* e = y::Find(*entries, key)) {
      auto v = y::Double(source, e->value, section + "." + key);
      TPCAL_RETURN_IF_ERROR(v);
      *target = *v;
    }
  }
  if (vector3 != nullptr) {
    if (const y::MapEntry* e = y::Find(*entries, vector3_key)) {
      auto v = y::Vector3(source, e->value, section + "." + vector3_key);
      TPCAL_RETURN_IF_ERROR(v);
      *vector3 = *v;
    }
  }
  return {};
}

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v == 0.0 ? 0.0 : v);
  return buf;
}

}  // namespace

Result<ProcessEffects> ParseProcessEffects(std::string_view yaml_text, const std::string& source) {
  auto root = y::Parse(std::string(yaml_text), source);
  TPCAL_RETURN_IF_ERROR(root);
  ProcessEffects effects;
  if (root->IsNull()) return effects;
  auto entries = y::Entries(source, *root, "process effects");
  TPCAL_RETURN_IF_ERROR(entries);
  TPCAL_RETURN_IF_ERROR(y::CheckKeys(source, *entries, {"schema", "tool_deflection", "servo_reversal"}, "process effects"));
  if (const y::MapEntry* e = y::Find(*entries, "schema")) {
    auto s = y::String(source, e->value, "schema");
    TPCAL_RETURN_IF_ERROR(s);
    if (*s != kProcessSchema) return y::Error(source, e->value, std::string("schema: expected ") + kProcessSchema + ", got '" + EchoInput(*s) + "'");
  }
  if (const y::MapEntry* e = y::Find(*entries, "tool_deflection")) {
    ToolDeflectionModel d;
    TPCAL_RETURN_IF_ERROR(ReadNumbers(source, e->value, "tool_deflection",
                                      {{"specific_force_n_per_mm2", &d.specific_force_n_per_mm2},
                                       {"passive_ratio", &d.passive_ratio},
                                       {"feed_ratio", &d.feed_ratio},
                                       {"floor_axial_area_mm2", &d.floor_axial_area_mm2},
                                       {"scale", &d.scale}},
                                      &d.compliance_um_per_n, "compliance_um_per_n"));
    if (Status s = d.Validate(); !s.ok()) return Status(StatusCode::kInvalidArgument, s.message(), source, y::Line(e->key_node));
    effects.deflection = d;
  }
  if (const y::MapEntry* e = y::Find(*entries, "servo_reversal")) {
    ServoReversalModel s;
    TPCAL_RETURN_IF_ERROR(ReadNumbers(source, e->value, "servo_reversal",
                                      {{"spike_x_um", &s.spike_x_um},
                                       {"spike_y_um", &s.spike_y_um},
                                       {"decay_deg", &s.decay_deg},
                                       {"backlash_x_um", &s.backlash_x_um},
                                       {"backlash_y_um", &s.backlash_y_um}},
                                      nullptr, ""));
    if (Status st = s.Validate(); !st.ok())
      return Status(StatusCode::kInvalidArgument, st.message(), source, y::Line(e->key_node));
    effects.servo = s;
  }
  return effects;
}

Result<ProcessEffects> LoadProcessEffects(const std::string& path) {
  auto text = y::ReadFile(path);
  TPCAL_RETURN_IF_ERROR(text);
  return ParseProcessEffects(*text, path);
}

std::string FormatProcessEffects(const ProcessEffects& effects) {
  if (effects.empty()) return "{}\n";
  std::string out;
  if (const auto& d = effects.deflection) {
    out += "tool_deflection:\n";
    out += "  specific_force_n_per_mm2: " + Num(d->specific_force_n_per_mm2) + "\n";
    out += "  passive_ratio: " + Num(d->passive_ratio) + "\n";
    out += "  feed_ratio: " + Num(d->feed_ratio) + "\n";
    out += "  floor_axial_area_mm2: " + Num(d->floor_axial_area_mm2) + "\n";
    out += "  compliance_um_per_n: [" + Num(d->compliance_um_per_n.x()) + ", " + Num(d->compliance_um_per_n.y()) +
           ", " + Num(d->compliance_um_per_n.z()) + "]\n";
    out += "  scale: " + Num(d->scale) + "\n";
  }
  if (const auto& s = effects.servo) {
    out += "servo_reversal:\n";
    out += "  spike_x_um: " + Num(s->spike_x_um) + "\n";
    out += "  spike_y_um: " + Num(s->spike_y_um) + "\n";
    out += "  decay_deg: " + Num(s->decay_deg) + "\n";
    out += "  backlash_x_um: " + Num(s->backlash_x_um) + "\n";
    out += "  backlash_y_um: " + Num(s->backlash_y_um) + "\n";
  }
  return out;
}

}  // namespace tpcal::testpieces
