#include "gcode/options_yaml.h"

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include "core/input_echo.h"
#include "core/text_file.h"
#include "gcode/nc_format.h"

namespace tpcal::gcode {
namespace {

constexpr const char* kSchema = "tpcal.gcode/1";

Status Err(const std::string& src, const YAML::Node& n, const std::string& what) {
  const int line = n.Mark().line >= 0 ? n.Mark().line + 1 : 0;
  return Status(StatusCode::kParseError, what, src, static_cast<std::size_t>(line));
}

// Keys of a map node in order, rejecting duplicates.
Result<std::vector<std::pair<std::string, YAML::Node>>> Entries(const std::string& src, const YAML::Node& n,
                                                                 const std::string& what) {
  if (!n.IsMap()) return Err(src, n, what + ": expected a map");
  std::vector<std::pair<std::string, YAML::Node>> out;
  std::set<std::string> seen;
  for (auto it = n.begin(); it != n.end(); ++it) {
    const std::string key = it->first.as<std::string>();
    if (!seen.insert(key).second) return Err(src, it->first, what + ": duplicate key '" + EchoInput(key) + "'");
    out.emplace_back(key, it->second);
  }
  return out;
}

Result<double> Double(const std::string& src, const YAML::Node& n, const std::string& key) {
  if (!n.IsScalar()) return Err(src, n, key + ": expected a number");
  try {
    const double v = n.as<double>();
    if (!std::isfinite(v)) return Err(src, n, key + ": expected a finite number");
    return v;
  } catch (const YAML::Exception&) {
    return Err(src, n, key + ": expected a number, got '" + EchoInput(n.Scalar()) + "'");
  }
}

Result<int> Int(const std::string& src, const YAML::Node& n, const std::string& key) {
  if (!n.IsScalar()) return Err(src, n, key + ": expected an integer");
  try {
    return n.as<int>();
  } catch (const YAML::Exception&) {
    return Err(src, n, key + ": expected an integer, got '" + EchoInput(n.Scalar()) + "'");
  }
}

Result<bool> Bool(const std::string& src, const YAML::Node& n, const std::string& key) {
  if (!n.IsScalar()) return Err(src, n, key + ": expected true or false");
  try {
    return n.as<bool>();
  } catch (const YAML::Exception&) {
    return Err(src, n, key + ": expected true or false, got '" + EchoInput(n.Scalar()) + "'");
  }
}

Result<std::string> String(const std::string& src, const YAML::Node& n, const std::string& key) {
  if (n.IsNull()) return std::string();
  if (!n.IsScalar()) return Err(src, n, key + ": expected a string");
  return n.Scalar();
}

// A table of setters: key -> parse into the options.
using Setter = std::function<Status(const std::string& src, const YAML::Node& n, const std::string& key)>;

Setter D(double* out) {
  return [out](const std::string& src, const YAML::Node& n, const std::string& key) -> Status {
    auto v = Double(src, n, key);
    if (!v.ok()) return v.status();
    *out = *v;
    return Status::Ok();
  };
}
Setter I(int* out) {
  return [out](const std::string& src, const YAML::Node& n, const std::string& key) -> Status {
    auto v = Int(src, n, key);
    if (!v.ok()) return v.status();
    *out = *v;
    return Status::Ok();
  };
}
Setter B(bool* out) {
  return [out](const std::string& src, const YAML::Node& n, const std::string& key) -> Status {
    auto v = Bool(src, n, key);
    if (!v.ok()) return v.status();
    *out = *v;
    return Status::Ok();
  };
}
Setter S(std::string* out) {
  return [out](const std::string& src, const YAML::Node& n, const std::string& key) -> Status {
    auto v = String(src, n, key);
    if (!v.ok()) return v.status();
    *out = *v;
    return Status::Ok();
  };
}

Status ApplyMap(const std::string& src, const YAML::Node& node, const std::string& prefix,
                const std::map<std::string, Setter>& setters) {
  auto entries = Entries(src, node, prefix.empty() ? "gcode options" : prefix);
  if (!entries.ok()) return entries.status();
  for (const auto& [key, value] : *entries) {
    const std::string full = EchoInput(prefix.empty() ? key : prefix + "." + key);
    auto it = setters.find(key);
    if (it == setters.end()) {
      std::string known;
      for (const auto& [k, s] : setters) known += (known.empty() ? "" : ", ") + k;
      // Find the key node for the line.
      for (auto kv = node.begin(); kv != node.end(); ++kv) {
        if (kv->first.as<std::string>() == key) return Err(src, kv->first, "unknown key '" + full + "' (known: " + known + ")");
      }
      return Err(src, node, "unknown key '" + full + "'");
    }
    TPCAL_RETURN_IF_ERROR(it->second(src, value, full));
  }
  return Status::Ok();
}

Result<GcodeOptions> Parse(const std::string& src, const YAML::Node& root) {
  if (root.IsNull()) return GcodeOptions::ForDialect(Dialect::kLinuxCnc);
  if (!root.IsMap()) return Err(src, root, "gcode options: expected a map");
  auto entries = Entries(src, root, "gcode options");
  if (!entries.ok()) return entries.status();
  Dialect dialect = Dialect::kLinuxCnc;
  for (const auto& [key, value] : *entries) {
    if (key == "dialect") {
      auto s = String(src, value, "dialect");
      if (!s.ok()) return s.status();
      const auto d = DialectFromName(*s);
      if (!d) return Err(src, value, "dialect: expected fanuc, linuxcnc, sinumerik or heidenhain, got '" + EchoInput(*s) + "'");
      dialect = *d;
    }
    if (key == "schema") {
      auto s = String(src, value, "schema");
      if (!s.ok()) return s.status();
      if (*s != kSchema) return Err(src, value, std::string("schema: expected ") + kSchema + ", got '" + EchoInput(*s) + "'");
    }
  }
  GcodeOptions o = GcodeOptions::ForDialect(dialect);
  std::string ignore;
  std::map<std::string, Setter> top = {
      {"schema", S(&ignore)},
      {"dialect", S(&ignore)},
      {"program_name", S(&o.program_name)},
      {"program_number", I(&o.program_number)},
      {"date", S(&o.date)},
      {"generator", S(&o.generator)},
      {"work_offset", I(&o.work_offset)},
      {"block_start", I(&o.block_start)},
      {"block_step", I(&o.block_step)},
      {"linear_decimals", I(&o.linear_decimals)},
      {"rotary_decimals", I(&o.rotary_decimals)},
      {"default_tool_length_mm", D(&o.default_tool_length_mm)},
  };
  top["coolant"] = [&o](const std::string& s, const YAML::Node& n, const std::string& key) -> Status {
    auto v = String(s, n, key);
    if (!v.ok()) return v.status();
    for (Coolant c : {Coolant::kOff, Coolant::kFlood, Coolant::kMist}) {
      if (*v == CoolantName(c)) {
        o.coolant = c;
        return Status::Ok();
      }
    }
    return Err(s, n, key + ": expected off, flood or mist, got '" + EchoInput(*v) + "'");
  };
  top["five_axis"] = [&o](const std::string& s, const YAML::Node& n, const std::string& key) -> Status {
    auto v = String(s, n, key);
    if (!v.ok()) return v.status();
    for (FiveAxisMode m : {FiveAxisMode::kJointInverseTime, FiveAxisMode::kToolCenterPoint}) {
      if (*v == FiveAxisModeName(m)) {
        o.five_axis = m;
        return Status::Ok();
      }
    }
    return Err(s, n, key + ": expected joint_inverse_time or tcp, got '" + EchoInput(*v) + "'");
  };
  top["tools"] = [&o](const std::string& s, const YAML::Node& n, const std::string& key) -> Status {
    if (!n.IsSequence()) return Err(s, n, key + ": expected a list of {piece_tool, number, length_mm}");
    o.tools.clear();
    for (std::size_t i = 0; i < n.size(); ++i) {
      ToolSetting t;
      const std::string k = key + "[" + std::to_string(i) + "]";
      TPCAL_RETURN_IF_ERROR(ApplyMap(s, n[i], k,
                                     {{"piece_tool", I(&t.piece_tool)}, {"number", I(&t.number)}, {"length_mm", D(&t.length_mm)}}));
      o.tools.push_back(t);
    }
    return Status::Ok();
  };
  CSpindleOptions& c = o.c_spindle;
  top["c_spindle"] = [&c](const std::string& s, const YAML::Node& n, const std::string& key) -> Status {
    return ApplyMap(s, n, key,
                    {{"mode_on_mcode", I(&c.mode_on_mcode)},
                     {"mode_off_mcode", I(&c.mode_off_mcode)},
                     {"spindle_number", I(&c.spindle_number)},
                     {"css", B(&c.css)},
                     {"max_rpm", D(&c.max_rpm)},
                     {"orient_mcode", I(&c.orient_mcode)},
                     {"orient_angle_deg", D(&c.orient_angle_deg)},
                     {"positive_c_mcode", I(&c.positive_c_mcode)},
                     {"heidenhain_start_mcode", I(&c.heidenhain_start_mcode)},
                     {"heidenhain_x_diameter", B(&c.heidenhain_x_diameter)},
                     {"linuxcnc_mode_bit", I(&c.linuxcnc_mode_bit)},
                     {"linuxcnc_speed_channel", I(&c.linuxcnc_speed_channel)},
                     {"css_step_mm", D(&c.css_step_mm)}});
  };
  SafetyOptions& sf = o.safety;
  top["safety"] = [&sf](const std::string& s, const YAML::Node& n, const std::string& key) -> Status {
    return ApplyMap(s, n, key,
                    {{"check_strokes", B(&sf.check_strokes)},
                     {"check_rapids", B(&sf.check_rapids)},
                     {"check_tool_fit", B(&sf.check_tool_fit)},
                     {"rapid_tolerance_mm", D(&sf.rapid_tolerance_mm)},
                     {"rapid_sample_mm", D(&sf.rapid_sample_mm)},
                     {"tool_fit_tol_mm", D(&sf.tool_fit_tol_mm)}});
  };
  BackplotOptions& bp = o.backplot;
  top["backplot"] = [&bp](const std::string& s, const YAML::Node& n, const std::string& key) -> Status {
    return ApplyMap(s, n, key, {{"width_px", D(&bp.width_px)}, {"arc_segment_deg", D(&bp.arc_segment_deg)}});
  };
  TPCAL_RETURN_IF_ERROR(ApplyMap(src, root, "", top));
  const Status valid = o.Validate();
  if (!valid.ok()) return Status(StatusCode::kInvalidArgument, valid.message(), src);
  return o;
}

std::string Q(const std::string& s) {
  std::string out = "\"";
  for (char ch : s) {
    if (ch == '"' || ch == '\\') out += '\\';
    out += ch;
  }
  return out + "\"";
}

std::string N(double v) { return FormatNumber(v, 9); }

}  // namespace

Result<GcodeOptions> ParseGcodeOptions(std::string_view yaml_text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(std::string(yaml_text));
  } catch (const YAML::DeepRecursion& e) {
    return Status(StatusCode::kParseError, "YAML nested " + std::to_string(e.depth()) + " levels deep; expected a configuration, not nested lists or maps", source, static_cast<std::size_t>(e.mark.line + 1));
  } catch (const YAML::ParserException& e) {
    return Status(StatusCode::kParseError, EchoInput(e.msg, 2 * kMaxEchoBytes), source, static_cast<std::size_t>(e.mark.line + 1));
  } catch (const YAML::Exception& e) {
    return Status(StatusCode::kParseError, EchoInput(e.what(), 2 * kMaxEchoBytes), source);
  }
  try {
    return Parse(source, root);
  } catch (const YAML::Exception& e) {
    return Status(StatusCode::kParseError, EchoInput(e.what(), 2 * kMaxEchoBytes), source);
  }
}

Result<GcodeOptions> LoadGcodeOptions(const std::string& path) {
  Result<std::string> text = ReadTextFile(path, "cannot open gcode options file");
  if (!text.ok()) return text.status();
  return ParseGcodeOptions(*text, path);
}

std::string FormatGcodeOptions(const GcodeOptions& o) {
  std::ostringstream os;
  const auto b = [](bool v) { return v ? "true" : "false"; };
  os << "schema: " << kSchema << "\n";
  os << "dialect: " << DialectName(o.dialect) << "\n";
  os << "program_name: " << o.program_name << "\n";
  os << "program_number: " << o.program_number << "\n";
  os << "date: " << Q(o.date) << "\n";
  os << "generator: " << Q(o.generator) << "\n";
  os << "work_offset: " << o.work_offset << "\n";
  os << "coolant: " << CoolantName(o.coolant) << "\n";
  os << "block_start: " << o.block_start << "\n";
  os << "block_step: " << o.block_step << "\n";
  os << "linear_decimals: " << o.linear_decimals << "\n";
  os << "rotary_decimals: " << o.rotary_decimals << "\n";
  os << "default_tool_length_mm: " << N(o.default_tool_length_mm) << "\n";
  os << "five_axis: " << FiveAxisModeName(o.five_axis) << "\n";
  os << "tools:" << (o.tools.empty() ? " []" : "") << "\n";
  for (const ToolSetting& t : o.tools) {
    os << "  - {piece_tool: " << t.piece_tool << ", number: " << t.number << ", length_mm: " << N(t.length_mm) << "}\n";
  }
  const CSpindleOptions& c = o.c_spindle;
  os << "c_spindle:\n"
     << "  mode_on_mcode: " << c.mode_on_mcode << "\n"
     << "  mode_off_mcode: " << c.mode_off_mcode << "\n"
     << "  spindle_number: " << c.spindle_number << "\n"
     << "  css: " << b(c.css) << "\n"
     << "  max_rpm: " << N(c.max_rpm) << "\n"
     << "  orient_mcode: " << c.orient_mcode << "\n"
     << "  orient_angle_deg: " << N(c.orient_angle_deg) << "\n"
     << "  positive_c_mcode: " << c.positive_c_mcode << "\n"
     << "  heidenhain_start_mcode: " << c.heidenhain_start_mcode << "\n"
     << "  heidenhain_x_diameter: " << b(c.heidenhain_x_diameter) << "\n"
     << "  linuxcnc_mode_bit: " << c.linuxcnc_mode_bit << "\n"
     << "  linuxcnc_speed_channel: " << c.linuxcnc_speed_channel << "\n"
     << "  css_step_mm: " << N(c.css_step_mm) << "\n";
  const SafetyOptions& s = o.safety;
  os << "safety:\n"
     << "  check_strokes: " << b(s.check_strokes) << "\n"
     << "  check_rapids: " << b(s.check_rapids) << "\n"
     << "  check_tool_fit: " << b(s.check_tool_fit) << "\n"
     << "  rapid_tolerance_mm: " << N(s.rapid_tolerance_mm) << "\n"
     << "  rapid_sample_mm: " << N(s.rapid_sample_mm) << "\n"
     << "  tool_fit_tol_mm: " << N(s.tool_fit_tol_mm) << "\n";
  os << "backplot:\n"
     << "  width_px: " << N(o.backplot.width_px) << "\n"
     << "  arc_segment_deg: " << N(o.backplot.arc_segment_deg) << "\n";
  return os.str();
}

}  // namespace tpcal::gcode
