#include "testpieces/piece_config.h"

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/yaml.h>

#include <charconv>
#include <cstdio>
#include <cstring>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <variant>

#include "core/input_echo.h"
#include "core/text_file.h"

namespace tpcal::testpieces {
namespace {

constexpr const char* kPieceSchema = "tpcal.testpiece/1";

// A parameter bound to a member of a parameter struct: dotted YAML path and member pointer.
template <class P>
struct Field {
  std::string path;
  std::variant<double P::*, int P::*, bool P::*, std::string P::*> member;
};

template <class P>
using Table = std::vector<Field<P>>;

Table<TurningPieceParams> TurningTable() {
  using T = TurningPieceParams;
  return {
      {"name", &T::name},
      {"groove.bottom_z_mm", &T::groove_bottom_z_mm},
      {"groove.depth_mm", &T::groove_depth_mm},
      {"groove.outer_radius_mm", &T::groove_outer_radius_mm},
      {"groove.inner_radius_mm", &T::groove_inner_radius_mm},
      {"groove.wall_probe_height_mm", &T::groove_wall_probe_height_mm},
      {"groove.floor_probe_radius_mm", &T::groove_floor_probe_radius_mm},
      {"groove.finish_stock_mm", &T::groove_finish_stock_mm},
      {"groove.wall_lift_mm", &T::groove_wall_lift_mm},
      {"groove.inner_wall_pass", &T::groove_inner_wall_pass},
      {"groove.outer_wall_ccw", &T::groove_outer_wall_ccw},
      {"holes.count", &T::hole_count},
      {"holes.pitch_radius_mm", &T::hole_pitch_radius_mm},
      {"holes.depth_mm", &T::hole_depth_mm},
      {"holes.probe_depth_mm", &T::hole_probe_depth_mm},
      {"base.radius_mm", &T::base_radius_mm},
      {"base.bottom_z_mm", &T::base_bottom_z_mm},
      {"base.bore_radius_mm", &T::bore_radius_mm},
      {"base.bore_top_z_mm", &T::bore_top_z_mm},
      {"bottom_probe_fraction", &T::bottom_probe_fraction},
      {"end_mill.diameter_mm", &T::end_mill_diameter_mm},
      {"end_mill.corner_radius_mm", &T::end_mill_corner_radius_mm},
      {"end_mill.teeth", &T::end_mill_teeth},
      {"end_mill.floor_cutting_speed_m_per_min", &T::floor_cutting_speed_m_per_min},
      {"end_mill.floor_feed_per_tooth_mm", &T::floor_feed_per_tooth_mm},
      {"end_mill.wall_cutting_speed_m_per_min", &T::wall_cutting_speed_m_per_min},
      {"end_mill.wall_feed_per_tooth_mm", &T::wall_feed_per_tooth_mm},
      {"reamer.diameter_mm", &T::reamer_diameter_mm},
      {"reamer.teeth", &T::reamer_teeth},
      {"reamer.cutting_speed_m_per_min", &T::reamer_cutting_speed_m_per_min},
      {"reamer.feed_per_tooth_mm", &T::reamer_feed_per_tooth_mm},
      {"turning_tool.nose_radius_mm", &T::insert_nose_radius_mm},
      {"turning_tool.included_angle_deg", &T::insert_included_angle_deg},
      {"turning_tool.cutting_speed_m_per_min", &T::turning_cutting_speed_m_per_min},
      {"turning_tool.feed_mm_per_rev", &T::turning_feed_mm_per_rev},
      {"turning_tool.depth_of_cut_mm", &T::turning_depth_of_cut_mm},
      {"turning_tool.max_table_rpm", &T::turning_max_table_rpm},
      {"turning_tool.reach_mm", &T::turning_tool_reach_mm},
      {"turning_tool.shank_width_mm", &T::turning_shank_width_mm},
      {"approach_clearance_mm", &T::approach_clearance_mm},
      {"safe_clearance_mm", &T::safe_clearance_mm},
  };
}

Table<TurnedStep> StepTable() {
  return {{"radius_mm", &TurnedStep::radius_mm},
          {"shoulder_z_mm", &TurnedStep::shoulder_z_mm},
          {"probe_z_mm", &TurnedStep::probe_z_mm}};
}

Table<ContourPieceParams> ContourTable() {
  using T = ContourPieceParams;
  return {
      {"name", &T::name},
      {"size_mm", &T::size_mm},
      {"base_thickness_mm", &T::base_thickness_mm},
      {"square.side_mm", &T::square_side_mm},
      {"square.height_mm", &T::square_height_mm},
      {"diamond.side_mm", &T::diamond_side_mm},
      {"diamond.height_mm", &T::diamond_height_mm},
      {"circle.diameter_mm", &T::circle_diameter_mm},
      {"circle.height_mm", &T::circle_height_mm},
      {"slopes.half_length_mm", &T::slope_half_length_mm},
      {"slopes.offset_mm", &T::slope_offset_mm},
      {"slopes.small_angle_deg", &T::slope_small_angle_deg},
      {"slopes.large_angle_deg", &T::slope_large_angle_deg},
      {"slopes.height_mm", &T::slope_height_mm},
      {"bore.diameter_mm", &T::bore_diameter_mm},
      {"end_mill.diameter_mm", &T::end_mill_diameter_mm},
      {"end_mill.teeth", &T::end_mill_teeth},
      {"end_mill.cutting_speed_m_per_min", &T::cutting_speed_m_per_min},
      {"end_mill.feed_per_tooth_mm", &T::feed_per_tooth_mm},
      {"probe_height_fraction", &T::probe_height_fraction},
      {"safe_clearance_mm", &T::safe_clearance_mm},
  };
}

Table<FaceMillingPieceParams> FaceMillingTable() {
  using T = FaceMillingPieceParams;
  return {
      {"name", &T::name},
      {"face_mill.diameter_mm", &T::face_mill_diameter_mm},
      {"face_mill.teeth", &T::face_mill_teeth},
      {"face_mill.cutting_speed_m_per_min", &T::cutting_speed_m_per_min},
      {"face_mill.feed_per_tooth_mm", &T::feed_per_tooth_mm},
      {"passes", &T::passes},
      {"overlap_fraction", &T::overlap_fraction},
      {"length_mm", &T::length_mm},
      {"height_mm", &T::height_mm},
      {"edge_clearance_mm", &T::edge_clearance_mm},
      {"run_out_mm", &T::run_out_mm},
      {"safe_clearance_mm", &T::safe_clearance_mm},
  };
}

Table<ConeFrustumParams> ConeTable() {
  using T = ConeFrustumParams;
  return {
      {"name", &T::name},
      {"base.size_mm", &T::base_size_mm},
      {"base.thickness_mm", &T::base_thickness_mm},
      {"cone.bottom_diameter_mm", &T::bottom_diameter_mm},
      {"cone.half_angle_deg", &T::half_angle_deg},
      {"cone.axis_tilt_deg", &T::axis_tilt_deg},
      {"cone.height_mm", &T::height_mm},
      {"end_mill.diameter_mm", &T::end_mill_diameter_mm},
      {"end_mill.teeth", &T::end_mill_teeth},
      {"end_mill.cutting_speed_m_per_min", &T::cutting_speed_m_per_min},
      {"end_mill.feed_per_tooth_mm", &T::feed_per_tooth_mm},
      {"tip_clearance_mm", &T::tip_clearance_mm},
      {"path_steps", &T::path_steps},
      {"probe_band_margin_mm", &T::probe_band_margin_mm},
      {"safe_clearance_mm", &T::safe_clearance_mm},
      {"second_cone.offset_mm", &T::second_cone_offset_mm},
      {"third_cone.offset_mm", &T::third_cone_offset_mm},
  };
}

Table<ProbingOptions> ProbingTable() {
  using T = ProbingOptions;
  return {{"points_per_circle", &T::points_per_circle}, {"levels_per_face", &T::levels_per_face},
          {"points_per_hole", &T::points_per_hole},     {"levels_per_hole", &T::levels_per_hole},
          {"points_per_line", &T::points_per_line},     {"grid_per_side", &T::grid_per_side},
          {"edge_margin_mm", &T::edge_margin_mm}};
}

Table<ProcessModel> ProcessTable() {
  using T = ProcessModel;
  return {{"rapid_mm_per_min", &T::rapid_mm_per_min},
          {"rotary_rapid_deg_per_s", &T::rotary_rapid_deg_per_s},
          {"tool_change_s", &T::tool_change_s},
          {"spindle_start_s", &T::spindle_start_s}};
}

// ---------------------------------------------------------------- parsing

class Parser {
 public:
  explicit Parser(std::string source) : source_(std::move(source)) {}

  Status Error(const YAML::Node& node, const std::string& what) const {
    const std::size_t line = node.Mark().is_null() ? 0 : static_cast<std::size_t>(node.Mark().line + 1);
    return Status(StatusCode::kParseError, what, source_, line);
  }

  // Checks `node` is a map without duplicate keys; returns its (key, value) pairs in order.
  Result<std::vector<std::pair<YAML::Node, YAML::Node>>> Entries(const YAML::Node& node, const std::string& where) const {
    if (!node.IsMap()) return Error(node, where + ": expected a map");
    std::vector<std::pair<YAML::Node, YAML::Node>> out;
    std::set<std::string> seen;
    for (const auto& kv : node) {
      if (!kv.first.IsScalar()) return Error(kv.first, where + ": keys must be plain names");
      const std::string key = kv.first.Scalar();
      if (!seen.insert(key).second) return Error(kv.first, where + ": duplicate key '" + EchoInput(key) + "'");
      out.emplace_back(kv.first, kv.second);
    }
    return out;
  }

  template <class P>
  Status Scalar(const YAML::Node& value, const std::string& path, const Field<P>& field, P* target) const {
    if (!value.IsScalar()) return Error(value, path + ": expected a single value");
    const std::string text = value.Scalar();
    return std::visit(
        [&](auto member) -> Status {
          using M = std::remove_reference_t<decltype(target->*member)>;
          if constexpr (std::is_same_v<M, double>) {
            double v = 0;
            const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
            if (r.ec != std::errc() || r.ptr != text.data() + text.size() || !std::isfinite(v)) {
              return Error(value, path + ": expected a finite number, got '" + EchoInput(text) + "'");
            }
            target->*member = v;
          } else if constexpr (std::is_same_v<M, int>) {
            long long v = 0;
            const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
            if (r.ec != std::errc() || r.ptr != text.data() + text.size() || v < -1000000000 || v > 1000000000) {
              return Error(value, path + ": expected an integer, got '" + EchoInput(text) + "'");
            }
            target->*member = static_cast<int>(v);
          } else if constexpr (std::is_same_v<M, bool>) {
            if (text == "true") {
              target->*member = true;
            } else if (text == "false") {
              target->*member = false;
            } else {
              return Error(value, path + ": expected true or false, got '" + EchoInput(text) + "'");
            }
          } else {
            target->*member = text;
          }
          return Status::Ok();
        },
        field.member);
  }

  // Walks a (nested) map and fills the fields of `table`; unknown keys are errors.
  template <class P>
  Status Fill(const YAML::Node& node, const std::string& prefix, const std::string& section, const Table<P>& table,
              P* target, const std::set<std::string>& skip = {}) const {
    auto entries = Entries(node, section + (prefix.empty() ? "" : "." + prefix.substr(0, prefix.size() - 1)));
    if (!entries.ok()) return entries.status();
    for (const auto& [k, v] : *entries) {
      const std::string path = prefix + k.Scalar();
      if (skip.count(path)) continue;
      const Field<P>* field = nullptr;
      bool is_group = false;
      for (const auto& f : table) {
        if (f.path == path) field = &f;
        if (f.path.rfind(path + ".", 0) == 0) is_group = true;
      }
      if (field) {
        TPCAL_RETURN_IF_ERROR(Scalar(v, section + "." + path, *field, target));
      } else if (is_group) {
        TPCAL_RETURN_IF_ERROR(Fill(v, path + ".", section, table, target, skip));
      } else {
        return Error(k, "unknown key '" + section + "." + EchoInput(path) + "'" + Expected(table, prefix));
      }
    }
    return Status::Ok();
  }

  template <class P>
  static std::string Expected(const Table<P>& table, const std::string& prefix) {
    std::set<std::string> names;
    for (const auto& f : table) {
      if (f.path.rfind(prefix, 0) != 0) continue;
      const std::string rest = f.path.substr(prefix.size());
      names.insert(rest.substr(0, rest.find('.')));
    }
    std::string out = " (expected one of:";
    for (const auto& n : names) out += " " + n;
    return out + ")";
  }

  Status Steps(const YAML::Node& node, TurningPieceParams* p) const {
    if (!node.IsSequence() || node.size() != p->steps.size()) {
      return Error(node, "turning.steps: expected a list of " + std::to_string(p->steps.size()) +
                             " steps (S1 .. S6), each {radius_mm, shoulder_z_mm, probe_z_mm}");
    }
    const auto table = StepTable();
    for (std::size_t i = 0; i < node.size(); ++i) {
      TPCAL_RETURN_IF_ERROR(Fill(node[i], "", "turning.steps[" + std::to_string(i) + "]", table, &p->steps[i]));
    }
    return Status::Ok();
  }

  Result<PieceConfig> Parse(std::string_view text) const {
    YAML::Node root;
    try {
      root = YAML::Load(std::string(text));
    } catch (const YAML::DeepRecursion& e) {
      return Status(StatusCode::kParseError, "YAML nested " + std::to_string(e.depth()) + " levels deep; expected a configuration, not nested lists or maps", source_, static_cast<std::size_t>(e.mark.line + 1));
    } catch (const YAML::ParserException& e) {
      return Status(StatusCode::kParseError, "YAML syntax: " + EchoInput(e.msg, 2 * kMaxEchoBytes), source_, static_cast<std::size_t>(e.mark.line + 1));
    }
    PieceConfig config;
    if (!root || root.IsNull()) return config;  // empty file: the seed 002 piece
    auto entries = Entries(root, "test-piece config");
    if (!entries.ok()) return entries.status();
    std::map<std::string, std::pair<YAML::Node, YAML::Node>> by_key;
    for (const auto& kv : *entries) by_key[kv.first.Scalar()] = kv;
    static const std::set<std::string> kTop = {"schema", "piece", "turning", "iso10791_m1", "iso10791_m2",
                                               "cone_frustum", "probing", "process"};
    for (const auto& kv : *entries) {
      if (!kTop.count(kv.first.Scalar())) {
        return Error(kv.first, "unknown key '" + EchoInput(kv.first.Scalar()) +
                                   "' (expected schema, piece, turning, iso10791_m1, iso10791_m2, cone_frustum, "
                                   "probing, process)");
      }
    }
    if (by_key.count("schema")) {
      const YAML::Node& v = by_key["schema"].second;
      if (!v.IsScalar() || v.Scalar() != kPieceSchema) return Error(v, std::string("schema: expected ") + kPieceSchema);
    }
    std::string piece = "turning";
    if (by_key.count("piece")) {
      const YAML::Node& v = by_key["piece"].second;
      if (!v.IsScalar()) return Error(v, "piece: expected a name");
      piece = v.Scalar();
    }
    for (const char* section : {"turning", "iso10791_m1", "iso10791_m2", "cone_frustum"}) {
      if (by_key.count(section) && piece != section) {
        return Error(by_key[section].first, std::string("section '") + section + "' does not match piece: " + EchoInput(piece));
      }
    }
    // An absent or empty (null) section means the defaults.
    const bool has_section = by_key.count(piece) && !by_key[piece].second.IsNull();
    const YAML::Node params = has_section ? by_key[piece].second : YAML::Node();
    if (piece == "turning") {
      TurningPieceParams p;
      if (has_section) {
        TPCAL_RETURN_IF_ERROR(Fill(params, "", "turning", TurningTable(), &p, {"steps"}));
        if (params.IsMap() && params["steps"]) TPCAL_RETURN_IF_ERROR(Steps(params["steps"], &p));
      }
      config.params = p;
    } else if (piece == "iso10791_m1") {
      ContourPieceParams p;
      if (has_section && params.IsMap() && params["size_mm"]) {
        ContourPieceParams probe;
        TPCAL_RETURN_IF_ERROR(Scalar(params["size_mm"], "iso10791_m1.size_mm", ContourTable()[1], &probe));
        if (!(probe.size_mm > 0)) return Error(params["size_mm"], "iso10791_m1.size_mm: must be > 0");
        p = ContourPieceParams::ForSize(probe.size_mm);
      }
      if (has_section) TPCAL_RETURN_IF_ERROR(Fill(params, "", "iso10791_m1", ContourTable(), &p));
      config.params = p;
    } else if (piece == "iso10791_m2") {
      FaceMillingPieceParams p;
      if (has_section) TPCAL_RETURN_IF_ERROR(Fill(params, "", "iso10791_m2", FaceMillingTable(), &p));
      config.params = p;
    } else if (piece == "cone_frustum") {
      ConeFrustumParams p;
      if (has_section) TPCAL_RETURN_IF_ERROR(Fill(params, "", "cone_frustum", ConeTable(), &p));
      config.params = p;
    } else {
      return Error(by_key["piece"].second,
                   "piece: expected turning, iso10791_m1, iso10791_m2 or cone_frustum, got '" + EchoInput(piece) + "'");
    }
    if (by_key.count("probing") && !by_key["probing"].second.IsNull()) {
      TPCAL_RETURN_IF_ERROR(Fill(by_key["probing"].second, "", "probing", ProbingTable(), &config.probing));
    }
    if (by_key.count("process") && !by_key["process"].second.IsNull()) {
      TPCAL_RETURN_IF_ERROR(Fill(by_key["process"].second, "", "process", ProcessTable(), &config.process));
    }
    Status valid = config.Validate();
    if (!valid.ok()) return Status(StatusCode::kInvalidArgument, valid.message(), source_);
    return config;
  }

 private:
  std::string source_;
};

// ---------------------------------------------------------------- formatting

std::string Number(double v) {
  char buf[40];
  for (int precision = 15; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof(buf), "%.*g", precision, v);
    double back = 0;
    std::from_chars(buf, buf + std::strlen(buf), back);
    if (back == v) break;
  }
  return buf;
}

std::string Quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

template <class P>
std::string Value(const P& p, const Field<P>& f) {
  return std::visit(
      [&](auto member) -> std::string {
        using M = std::remove_cv_t<std::remove_reference_t<decltype(p.*member)>>;
        if constexpr (std::is_same_v<M, double>) return Number(p.*member);
        else if constexpr (std::is_same_v<M, int>) return std::to_string(p.*member);
        else if constexpr (std::is_same_v<M, bool>) return p.*member ? "true" : "false";
        else return Quoted(p.*member);
      },
      f.member);
}

// Writes the fields as nested maps, in table order, grouping consecutive fields by section.
template <class P>
void Emit(std::ostringstream& os, const P& p, const Table<P>& table, int indent) {
  std::string open_group;
  for (const auto& f : table) {
    const auto dot = f.path.find('.');
    const std::string group = dot == std::string::npos ? "" : f.path.substr(0, dot);
    const std::string key = dot == std::string::npos ? f.path : f.path.substr(dot + 1);
    if (group != open_group && !group.empty()) os << std::string(indent, ' ') << group << ":\n";
    open_group = group;
    os << std::string(indent + (group.empty() ? 0 : 2), ' ') << key << ": " << Value(p, f) << "\n";
  }
}

}  // namespace

Result<PieceConfig> ParsePieceConfig(std::string_view yaml_text, const std::string& source) {
  try {
    return Parser(source).Parse(yaml_text);
  } catch (const YAML::Exception& e) {
    return Status(StatusCode::kParseError, "YAML: " + EchoInput(e.what(), 2 * kMaxEchoBytes), source,
                  e.mark.is_null() ? 0 : static_cast<std::size_t>(e.mark.line + 1));
  }
}

Result<PieceConfig> LoadPieceConfig(const std::string& path) {
  Result<std::string> text = ReadTextFile(path, "cannot read the test-piece config");
  if (!text.ok()) return text.status();
  return ParsePieceConfig(*text, path);
}

std::string FormatPieceConfig(const PieceConfig& config) {
  std::ostringstream os;
  os << "# tpcal test-piece configuration (testpieces/piece_config.h, testpieces/README.md)\n";
  os << "schema: " << kPieceSchema << "\n";
  const PieceKind kind = KindOf(config.params);
  os << "piece: " << PieceKindName(kind) << "\n";
  os << PieceKindName(kind) << ":\n";
  if (const auto* p = std::get_if<TurningPieceParams>(&config.params)) {
    Emit(os, *p, TurningTable(), 2);
    os << "  steps:  # S1 .. S6: side face radius, shoulder (B_i) height, S_i probing height (z_i)\n";
    const auto table = StepTable();
    for (const TurnedStep& s : p->steps) {
      os << "    - {";
      for (std::size_t i = 0; i < table.size(); ++i) {
        os << (i ? ", " : "") << table[i].path << ": " << Value(s, table[i]);
      }
      os << "}\n";
    }
  } else if (const auto* p = std::get_if<ContourPieceParams>(&config.params)) {
    Emit(os, *p, ContourTable(), 2);
  } else if (const auto* p = std::get_if<FaceMillingPieceParams>(&config.params)) {
    Emit(os, *p, FaceMillingTable(), 2);
  } else if (const auto* p = std::get_if<ConeFrustumParams>(&config.params)) {
    Emit(os, *p, ConeTable(), 2);
  }
  os << "probing:\n";
  Emit(os, config.probing, ProbingTable(), 2);
  os << "process:\n";
  Emit(os, config.process, ProcessTable(), 2);
  return os.str();
}

}  // namespace tpcal::testpieces
