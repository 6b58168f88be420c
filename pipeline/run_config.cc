#include "pipeline/run_config.h"

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <map>
#include <set>
#include <type_traits>

#include "core/ascii.h"
#include "core/input_echo.h"
#include "core/text_file.h"
#include "kinematics/machine_yaml.h"
#include "pipeline/io/point_io.h"
#include "pipeline/reference_instruments.h"
#include "testpieces/named_pieces.h"
#include "testpieces/piece_config.h"

namespace tpcal::pipeline {
namespace {

namespace fs = std::filesystem;

Status ParseErrorAt(const std::string& source, const YAML::Node& node, const std::string& what) {
  const auto mark = node.Mark();
  return Status(StatusCode::kParseError, what, source,
                mark.line >= 0 ? static_cast<std::size_t>(mark.line) + 1 : 0);
}

// Path relative to the directory of `source` unless absolute or source is empty.
std::string Resolve(const std::string& source, const std::string& path) {
  if (path.empty() || source.empty() || fs::path(path).is_absolute()) return path;
  return (fs::path(source).parent_path() / path).lexically_normal().string();
}

// Text values (paths, names) reach messages, config.yaml and result.json: printable UTF-8 of at
// most kMaxConfigTextBytes.
constexpr std::size_t kMaxConfigTextBytes = 4096;
bool PrintableText(const std::string& s) {
  if (s.size() > kMaxConfigTextBytes || FirstInvalidUtf8(s) != std::string_view::npos) return false;
  for (char c : s)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) return false;
  return true;
}

template <typename T>
Result<T> As(const std::string& source, const YAML::Node& node, const std::string& key, const char* expected) {
  T value;
  try {
    value = node.as<T>();
  } catch (const YAML::Exception&) {
    return ParseErrorAt(source, node, "'" + EchoInput(key) + "': expected " + expected);
  }
  bool printable = true;
  if constexpr (std::is_same_v<T, std::string>) printable = PrintableText(value);
  if constexpr (std::is_same_v<T, std::vector<std::string>>)
    for (const std::string& v : value) printable = printable && PrintableText(v);
  if constexpr (std::is_same_v<T, std::map<std::string, std::string>>)
    for (const auto& [k, v] : value) printable = printable && PrintableText(k) && PrintableText(v);
  if (!printable)
    return ParseErrorAt(source, node, "'" + EchoInput(key) + "': expected " + expected +
                                          " in printable UTF-8 of at most " +
                                          std::to_string(kMaxConfigTextBytes) + " bytes");
  return value;
}

// reference: {instrument: NAME, file: PATH, setup: PATH, probe_radius_mm: R}: instrument (default
// datum_ball) and file; setup for probe_artifacts (optional) and ballbar; probe_radius_mm for
// probe_artifacts (> 0; default 3); paths relative to the YAML's directory.
Status ParseReferenceBlock(const std::string& source, const YAML::Node& v, PipelineConfig* c) {
  if (!v.IsMap())
    return ParseErrorAt(source, v,
                        "'reference': expected a map {instrument: datum_ball, file: PATH, setup: PATH, probe_radius_mm: R}");
  c->reference_instrument = "datum_ball";
  bool have_file = false;
  for (const auto& r : v) {
    const std::string k = r.first.as<std::string>();
    if (k != "instrument" && k != "file" && k != "setup" && k != "probe_radius_mm")
      return ParseErrorAt(source, r.first,
                          "unknown key 'reference." + EchoInput(k) + "' (expected instrument, file, setup, probe_radius_mm)");
    if (k == "probe_radius_mm") {
      auto d = As<double>(source, r.second, "reference.probe_radius_mm", "a stylus radius in mm > 0");
      if (!d.ok()) return d.status();
      if (!std::isfinite(*d) || !(*d > 0.0))
        return ParseErrorAt(source, r.second, "'reference.probe_radius_mm': expected a stylus radius in mm > 0");
      c->reference_probe_radius_mm = *d;
      continue;
    }
    auto s = As<std::string>(source, r.second, k, k == "instrument" ? kReferenceInstruments : "a path");
    if (!s.ok()) return s.status();
    if (k == "instrument" && !IsReferenceInstrument(*s))
      return ParseErrorAt(source, r.second, "'reference.instrument' '" + EchoInput(*s) + "': expected " + std::string(kReferenceInstruments));
    if (k != "instrument" && s->empty()) return ParseErrorAt(source, r.second, "'reference." + k + "': expected a path");
    if (k == "instrument") c->reference_instrument = *s;
    if (k == "file") c->reference_file = Resolve(source, *s);
    if (k == "setup") c->reference_setup = Resolve(source, *s);
    have_file = have_file || k == "file";
  }
  if (!have_file) return ParseErrorAt(source, v, "'reference': missing key 'file' (the instrument's file)");
  return Status::Ok();
}

}  // namespace

std::optional<kinematics::UncertaintyMethod> ParseUncertaintyMethod(const std::string& name) {
  using kinematics::UncertaintyMethod;
  for (auto m : {UncertaintyMethod::kAnalytic, UncertaintyMethod::kJackknifePoints,
                 UncertaintyMethod::kJackknifeGroups, UncertaintyMethod::kMonteCarlo})
    if (name == kinematics::UncertaintyMethodName(m)) return m;
  return std::nullopt;
}

Status PipelineConfig::Validate() const {
  if (points.empty()) return Status(StatusCode::kInvalidArgument, "no point file given ('points' / --points)", source);
  if (testpiece.empty()) return Status(StatusCode::kInvalidArgument, "'testpiece' is empty", source);
  if (monte_carlo_trials < 0 || monte_carlo_trials > 1000000)
    return Status(StatusCode::kInvalidArgument, "'monte_carlo_trials' must be in [0, 1e6]", source);
  if (primary == kinematics::UncertaintyMethod::kMonteCarlo && monte_carlo_trials == 0)
    return Status(StatusCode::kInvalidArgument, "primary uncertainty monte_carlo needs monte_carlo_trials > 0", source);
  if (primary == kinematics::UncertaintyMethod::kJackknifeGroups && !jackknife_groups)
    return Status(StatusCode::kInvalidArgument, "primary uncertainty jackknife_groups needs jackknife_groups: true",
                  source);
  if (!(figures.position_magnification > 0) || !(figures.profile_magnification > 0))
    return Status(StatusCode::kInvalidArgument, "report magnifications must be > 0", source);
  if (anchor_feature.empty() != !anchor_near_mm.has_value())
    return Status(StatusCode::kInvalidArgument, "'raw_scan': anchor_feature and anchor_near_mm go together", source);
  if (reference_file.empty() != reference_instrument.empty())
    return Status(StatusCode::kInvalidArgument, "'reference': instrument and file go together", source);
  if (!reference_instrument.empty() && !IsReferenceInstrument(reference_instrument))
    return Status(StatusCode::kInvalidArgument,
                  "'reference': instrument '" + EchoInput(reference_instrument) + "': expected " + std::string(kReferenceInstruments), source);
  if (!reference_setup.empty() && !ReferenceTakesSetup(reference_instrument))
    return Status(StatusCode::kInvalidArgument,
                  "'reference': setup is for probe_artifacts (its artifacts) or ballbar (its installations), not '" +
                      EchoInput(reference_instrument) + "'", source);
  if (reference_probe_radius_mm && reference_instrument.empty())
    return Status(StatusCode::kInvalidArgument,
                  "'reference': probe_radius_mm (--reference-probe-radius-mm) needs a probe_artifacts reference", source);
  if (reference_probe_radius_mm && reference_instrument != "probe_artifacts")
    return Status(StatusCode::kInvalidArgument,
                  "'reference': probe_radius_mm is for probe_artifacts (its stylus), not '" +
                      EchoInput(reference_instrument) + "'", source);
  if (reference_probe_radius_mm && !(std::isfinite(*reference_probe_radius_mm) && *reference_probe_radius_mm > 0.0))
    return Status(StatusCode::kInvalidArgument,
                  "'reference': probe_radius_mm (--reference-probe-radius-mm): expected a stylus radius in mm > 0", source);
  if (reference_instrument == "ballbar" && reference_setup.empty())
    return Status(StatusCode::kInvalidArgument,
                  "'reference': instrument ballbar needs its set-up (reference.setup / --reference-setup S.yaml, "
                  "tpcal.ballbar_setup/1)", source);
  if (Status s = scan_cells.Validate(); !s.ok()) return s.WithLocation(source);
  PointReadOptions read;
  read.columns = columns;
  if (Status s = read.Validate(); !s.ok()) return Status(s.code(), "'columns': " + s.message(), source);
  return Status::Ok();
}

Result<PipelineConfig> ApplyPipelineOverrides(PipelineConfig c, const PipelineOverrides& o, bool batch) {
  if (!o.testpiece.empty()) c.testpiece = o.testpiece;
  if (!o.points.empty()) c.points = o.points;
  if (!o.columns.empty()) {
    auto columns = ParsePointColumns(o.columns);
    if (!columns.ok()) return columns.status();
    c.columns = std::move(*columns);
  }
  if (!o.machine.empty()) c.machine = o.machine;
  if (!o.truth.empty()) c.truth = o.truth;
  if (!o.parameters.empty()) c.parameters = o.parameters;
  if (o.seed) c.seed = *o.seed;
  if (o.monte_carlo_trials) c.monte_carlo_trials = *o.monte_carlo_trials;
  if (o.keep_outliers) c.keep_outliers = true;
  if (!o.reference_file.empty()) c.reference_file = o.reference_file;
  if (!o.reference_instrument.empty()) c.reference_instrument = o.reference_instrument;
  if (!o.reference_setup.empty()) c.reference_setup = o.reference_setup;
  if (o.reference_probe_radius_mm) c.reference_probe_radius_mm = o.reference_probe_radius_mm;
  if (!o.out.empty()) c.out = o.out;
  if (!o.anchor_feature.empty()) {
    c.anchor_feature = o.anchor_feature;
    c.anchor_near_mm = o.anchor_near_mm;
  }
  if (batch && c.points.empty()) c.points = "(batch)";
  if (Status s = c.Validate(); !s.ok()) return s;
  if (c.out.empty())
    return Status(StatusCode::kInvalidArgument, "no output directory: give --out DIR (or 'out' in the pipeline file)");
  return c;
}

// The settings of a loaded pipeline document; yaml-cpp throws on node kinds the code does not
// expect (a map as a key), which the caller turns into a parse error.
static Result<PipelineConfig> ParsePipelineRoot(const YAML::Node& root, const std::string& source) {
  if (!root.IsMap()) return Status(StatusCode::kParseError, "expected a map of settings (tpcal.pipeline/1)", source, 1);
  PipelineConfig c;
  c.source = source;
  std::set<std::string> seen;
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    const YAML::Node& v = kv.second;
    if (!seen.insert(key).second) return ParseErrorAt(source, kv.first, "duplicate key '" + EchoInput(key) + "'");
    auto str = [&]() { return As<std::string>(source, v, key, "a string"); };
    if (key == "schema") {
      auto s = str();
      if (!s.ok()) return s.status();
      if (*s != "tpcal.pipeline/1")
        return ParseErrorAt(source, v, "schema '" + EchoInput(*s) + "' is not tpcal.pipeline/1");
    } else if (key == "testpiece") {
      auto s = str();
      if (!s.ok()) return s.status();
      c.testpiece = (s->ends_with(".yaml") || s->ends_with(".yml")) ? Resolve(source, *s) : *s;
    } else if (key == "points" || key == "machine" || key == "truth") {
      auto s = str();
      if (!s.ok()) return s.status();
      (key == "points" ? c.points : key == "machine" ? c.machine : c.truth) = Resolve(source, *s);
    } else if (key == "columns") {
      auto m = As<std::map<std::string, std::string>>(source, v, key, "a map of role: column name");
      if (!m.ok()) return m.status();
      c.columns.clear();
      for (const auto& [role, name] : *m) c.columns.emplace_back(AsciiLower(role), name);  // roles in any case
      PointReadOptions read;
      read.columns = c.columns;
      if (Status s = read.Validate(); !s.ok()) return ParseErrorAt(source, v, "'columns': " + s.message());
    } else if (key == "out") {
      auto s = str();
      if (!s.ok()) return s.status();
      c.out = *s;
    } else if (key == "parameters") {
      auto p = As<std::vector<std::string>>(source, v, key, "a list of parameter names");
      if (!p.ok()) return p.status();
      c.parameters = *p;
    } else if (key == "seed") {
      auto s = As<std::uint64_t>(source, v, key, "a non-negative integer");
      if (!s.ok()) return s.status();
      c.seed = *s;
    } else if (key == "diagnose") {
      auto b = As<bool>(source, v, key, "true or false");
      if (!b.ok()) return b.status();
      c.diagnose = *b;
    } else if (key == "keep_outliers") {
      auto b = As<bool>(source, v, key, "true or false");
      if (!b.ok()) return b.status();
      c.keep_outliers = *b;
    } else if (key == "reference") {
      if (Status s = ParseReferenceBlock(source, v, &c); !s.ok()) return s;
    } else if (key == "uncertainty") {
      if (!v.IsMap()) return ParseErrorAt(source, v, "'uncertainty': expected a map");
      for (const auto& u : v) {
        const std::string k = u.first.as<std::string>();
        if (k == "primary") {
          auto s = As<std::string>(source, u.second, k, "a method name");
          if (!s.ok()) return s.status();
          auto m = ParseUncertaintyMethod(*s);
          if (!m)
            return ParseErrorAt(source, u.second,
                                "'primary': expected analytic, jackknife_points, jackknife_groups or monte_carlo");
          c.primary = *m;
        } else if (k == "jackknife_groups") {
          auto b = As<bool>(source, u.second, k, "true or false");
          if (!b.ok()) return b.status();
          c.jackknife_groups = *b;
        } else if (k == "monte_carlo_trials") {
          auto n = As<int>(source, u.second, k, "an integer");
          if (!n.ok()) return n.status();
          c.monte_carlo_trials = *n;
        } else {
          return ParseErrorAt(source, u.first,
                              "unknown key 'uncertainty." + EchoInput(k) +
                                  "' (expected primary, jackknife_groups, monte_carlo_trials)");
        }
      }
    } else if (key == "raw_scan") {
      if (!v.IsMap()) return ParseErrorAt(source, v, "'raw_scan': expected a map");
      for (const auto& r : v) {
        const std::string k = r.first.as<std::string>();
        if (k == "anchor_feature") {
          auto f = As<std::string>(source, r.second, k, "a feature name");
          if (!f.ok()) return f.status();
          c.anchor_feature = *f;
        } else if (k == "anchor_near_mm") {
          auto p = As<std::vector<double>>(source, r.second, k, "a list [x, y, z] in mm");
          if (!p.ok()) return p.status();
          if (p->empty()) {
            c.anchor_near_mm.reset();
          } else if (p->size() == 3) {
            c.anchor_near_mm = Eigen::Vector3d((*p)[0], (*p)[1], (*p)[2]);
          } else {
            return ParseErrorAt(source, r.second, "'anchor_near_mm': expected [x, y, z] (mm) or []");
          }
        } else {
          return ParseErrorAt(source, r.first, "unknown key 'raw_scan." + EchoInput(k) + "' (expected anchor_feature, anchor_near_mm)");
        }
      }
    } else if (key == "scan_cells") {
      if (!v.IsMap()) return ParseErrorAt(source, v, "'scan_cells': expected a map");
      for (const auto& r : v) {
        const std::string k = r.first.as<std::string>();
        if (k == "above_points" || k == "target_cells") {
          auto n = As<std::uint64_t>(source, r.second, k, "a non-negative integer");
          if (!n.ok()) return n.status();
          (k == "above_points" ? c.scan_cells.above_points : c.scan_cells.target_cells) = *n;
        } else if (k == "max_cell_mm" || k == "max_cell_deg") {
          auto d = As<double>(source, r.second, k, "a number");
          if (!d.ok()) return d.status();
          (k == "max_cell_mm" ? c.scan_cells.max_cell_mm : c.scan_cells.max_cell_deg) = *d;
        } else {
          return ParseErrorAt(source, r.first,
                              "unknown key 'scan_cells." + EchoInput(k) +
                                  "' (expected above_points, target_cells, max_cell_mm, max_cell_deg)");
        }
      }
    } else if (key == "report") {
      if (!v.IsMap()) return ParseErrorAt(source, v, "'report': expected a map");
      for (const auto& r : v) {
        const std::string k = r.first.as<std::string>();
        if (k != "position_magnification" && k != "profile_magnification")
          return ParseErrorAt(source, r.first,
                              "unknown key 'report." + EchoInput(k) +
                                  "' (expected position_magnification, profile_magnification)");
        auto d = As<double>(source, r.second, k, "a number");
        if (!d.ok()) return d.status();
        (k == "position_magnification" ? c.figures.position_magnification : c.figures.profile_magnification) = *d;
      }
    } else {
      return ParseErrorAt(source, kv.first,
                          "unknown key '" + EchoInput(key) +
                              "' (expected schema, testpiece, points, columns, machine, parameters, seed, uncertainty, "
                              "diagnose, keep_outliers, truth, reference, raw_scan, scan_cells, report, out)");
    }
  }
  return c;
}

Result<PipelineConfig> ParsePipelineConfig(const std::string& yaml_text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::DeepRecursion& e) {
    return Status(StatusCode::kParseError, "YAML nested " + std::to_string(e.depth()) + " levels deep; expected a configuration, not nested lists or maps", source, static_cast<std::size_t>(e.mark.line) + 1);
  } catch (const YAML::ParserException& e) {
    return Status(StatusCode::kParseError, EchoInput(e.msg, 2 * kMaxEchoBytes), source, static_cast<std::size_t>(e.mark.line) + 1);
  }
  try {
    return ParsePipelineRoot(root, source);
  } catch (const YAML::Exception& e) {  // a list or map where a name or value belongs
    return Status(StatusCode::kParseError, "expected plain names and values of tpcal.pipeline/1 (YAML: " + EchoInput(e.msg, 2 * kMaxEchoBytes) + ")",
                  source, e.mark.is_null() ? 0 : static_cast<std::size_t>(e.mark.line) + 1);
  }
}

Result<PipelineConfig> LoadPipelineConfig(const std::string& path) {
  Result<std::string> text = ReadTextFile(path, "cannot open pipeline file");
  if (!text.ok()) return text.status();
  return ParsePipelineConfig(*text, path);
}

std::string FormatPipelineConfig(const PipelineConfig& c) {
  YAML::Emitter e;
  e << YAML::BeginMap;
  e << YAML::Key << "schema" << YAML::Value << "tpcal.pipeline/1";
  e << YAML::Key << "testpiece" << YAML::Value << c.testpiece;
  e << YAML::Key << "points" << YAML::Value << c.points;
  if (!c.columns.empty()) {  // written only when set: a run without a mapping echoes as before
    e << YAML::Key << "columns" << YAML::Value << YAML::BeginMap;
    for (const auto& [role, name] : c.columns) e << YAML::Key << role << YAML::Value << name;
    e << YAML::EndMap;
  }
  e << YAML::Key << "machine" << YAML::Value << c.machine;
  e << YAML::Key << "parameters" << YAML::Value << YAML::Flow << c.parameters;
  e << YAML::Key << "seed" << YAML::Value << c.seed;
  e << YAML::Key << "uncertainty" << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "primary" << YAML::Value << kinematics::UncertaintyMethodName(c.primary);
  e << YAML::Key << "jackknife_groups" << YAML::Value << c.jackknife_groups;
  e << YAML::Key << "monte_carlo_trials" << YAML::Value << c.monte_carlo_trials;
  e << YAML::EndMap;
  e << YAML::Key << "diagnose" << YAML::Value << c.diagnose;
  e << YAML::Key << "keep_outliers" << YAML::Value << c.keep_outliers;
  e << YAML::Key << "truth" << YAML::Value << c.truth;
  if (!c.reference_file.empty()) {  // written only when set: a run without one echoes as before
    e << YAML::Key << "reference" << YAML::Value << YAML::BeginMap;
    e << YAML::Key << "instrument" << YAML::Value << c.reference_instrument;
    e << YAML::Key << "file" << YAML::Value << c.reference_file;
    if (!c.reference_setup.empty()) e << YAML::Key << "setup" << YAML::Value << c.reference_setup;
    if (c.reference_probe_radius_mm)
      e << YAML::Key << "probe_radius_mm" << YAML::Value << *c.reference_probe_radius_mm;
    e << YAML::EndMap;
  }
  e << YAML::Key << "raw_scan" << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "anchor_feature" << YAML::Value << c.anchor_feature;
  std::vector<double> near;
  if (c.anchor_near_mm) near = {c.anchor_near_mm->x(), c.anchor_near_mm->y(), c.anchor_near_mm->z()};
  e << YAML::Key << "anchor_near_mm" << YAML::Value << YAML::Flow << near;
  e << YAML::EndMap;
  e << YAML::Key << "scan_cells" << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "above_points" << YAML::Value << c.scan_cells.above_points;
  e << YAML::Key << "target_cells" << YAML::Value << c.scan_cells.target_cells;
  e << YAML::Key << "max_cell_mm" << YAML::Value << c.scan_cells.max_cell_mm;
  e << YAML::Key << "max_cell_deg" << YAML::Value << c.scan_cells.max_cell_deg;
  e << YAML::EndMap;
  e << YAML::Key << "report" << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "position_magnification" << YAML::Value << c.figures.position_magnification;
  e << YAML::Key << "profile_magnification" << YAML::Value << c.figures.profile_magnification;
  e << YAML::EndMap;
  e << YAML::Key << "out" << YAML::Value << c.out;
  e << YAML::EndMap;
  return std::string(e.c_str()) + "\n";
}

}  // namespace tpcal::pipeline
