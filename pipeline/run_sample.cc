#include "pipeline/run_sample.h"

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <set>

#include "core/input_echo.h"
#include "core/text_file.h"
#include "kinematics/errors_yaml.h"
#include "testpieces/probing_plan.h"

namespace tpcal::pipeline {
namespace {

namespace fs = std::filesystem;

Status At(const std::string& source, const YAML::Node& node, const std::string& what) {
  const auto mark = node.Mark();
  return Status(StatusCode::kParseError, what, source, mark.line >= 0 ? static_cast<std::size_t>(mark.line) + 1 : 0);
}

std::string ResolveTruthPath(const std::string& source, const std::string& path) {
  if (path.empty() || fs::path(path).is_absolute()) return path;
  return (fs::path(source).parent_path() / path).lexically_normal().string();
}

}  // namespace

Result<SampleTruth> LoadSampleTruth(const std::string& path) {
  Result<std::string> text = ReadTextFile(path, "cannot open truth file");
  if (!text.ok()) return text.status();
  YAML::Node root;
  try {
    root = YAML::Load(*text);
  } catch (const YAML::DeepRecursion& e) {
    return Status(StatusCode::kParseError, "YAML nested " + std::to_string(e.depth()) + " levels deep; expected a configuration, not nested lists or maps", path, static_cast<std::size_t>(e.mark.line) + 1);
  } catch (const YAML::ParserException& e) {
    return Status(StatusCode::kParseError, EchoInput(e.msg, 2 * kMaxEchoBytes), path, static_cast<std::size_t>(e.mark.line) + 1);
  }
  if (!root.IsMap()) return Status(StatusCode::kParseError, "expected a map (tpcal.sample_truth/1)", path, 1);
  SampleTruth t;
  t.source = path;
  bool have_errors = false;
  std::set<std::string> seen;
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    const YAML::Node& v = kv.second;
    if (!seen.insert(key).second) return At(path, kv.first, "duplicate key '" + key + "'");
    try {
      if (key == "schema") {
        if (v.as<std::string>() != "tpcal.sample_truth/1") return At(path, v, "schema must be tpcal.sample_truth/1");
      } else if (key == "description") {
        t.description = v.as<std::string>();
      } else if (key == "testpiece") {
        const auto s = v.as<std::string>();
        t.testpiece = (s.ends_with(".yaml") || s.ends_with(".yml")) ? ResolveTruthPath(path, s) : s;
      } else if (key == "machine") {
        t.machine = ResolveTruthPath(path, v.as<std::string>());
      } else if (key == "seed") {
        t.sim.seed = v.as<std::uint64_t>();
      } else if (key == "noise_um") {
        t.sim.noise_um = v.as<double>();
      } else if (key == "probe_radius_error_um") {
        t.sim.probe_radius_error_um = v.as<double>();
      } else if (key == "random_placement") {
        t.sim.random_placement = v.as<bool>();
      } else if (key == "points_per_circle") {
        t.points_per_circle = v.as<int>();
      } else if (key == "points_per_hole") {
        t.points_per_hole = v.as<int>();
      } else if (key == "levels_per_face") {
        t.levels_per_face = v.as<int>();
      } else if (key == "levels_per_hole") {
        t.levels_per_hole = v.as<int>();
      } else if (key == "raw_scan") {
        t.raw_scan = v.as<bool>();
      } else if (key == "errors") {
        if (!v.IsMap()) return At(path, v, "'errors': expected a tpcal.errors/1 map");
        YAML::Emitter e;
        e << v;
        t.errors_yaml = std::string(e.c_str()) + "\n";
        have_errors = true;
      } else {
        return At(path, kv.first,
                  "unknown key '" + key +
                      "' (expected schema, description, testpiece, machine, seed, noise_um, probe_radius_error_um, "
                      "random_placement, points_per_circle, points_per_hole, levels_per_face, levels_per_hole, "
                      "raw_scan, errors)");
      }
    } catch (const YAML::Exception&) {
      return At(path, v, "'" + key + "': wrong type");
    }
  }
  if (!have_errors) return Status(StatusCode::kParseError, "missing 'errors' (the stated machine errors)", path, 1);
  if (Status s = t.sim.Validate(); !s.ok()) return s.WithLocation(path);
  return t;
}

Result<SimulatedSample> SimulateSample(const SampleTruth& truth) {
  auto setup = LoadPiece({.testpiece = truth.testpiece, .machine_path = truth.machine, .allow_piece_file = true});
  if (!setup.ok()) return setup.status();
  auto errors = kinematics::ParseErrorState(truth.errors_yaml, truth.source + " (errors)", setup->machine);
  if (!errors.ok()) return errors.status();
  testpieces::PieceSimOptions sim = truth.sim;
  testpieces::ProbingOptions density = setup->piece.config.probing;
  if (truth.points_per_circle) density.points_per_circle = *truth.points_per_circle;
  if (truth.points_per_hole) density.points_per_hole = *truth.points_per_hole;
  if (truth.levels_per_face) density.levels_per_face = *truth.levels_per_face;
  if (truth.levels_per_hole) density.levels_per_hole = *truth.levels_per_hole;
  sim.density = density;
  if (Status s = density.Validate(); !s.ok()) return s.WithLocation(truth.source);
  if (Status s = testpieces::CheckPlanSize(setup->piece, density); !s.ok()) return s.WithLocation(truth.source);
  auto simulated = testpieces::SimulatePiece(setup->piece, setup->machine, *errors, sim);
  if (!simulated.ok()) return kinematics::AtErrorsFile(simulated.status(), truth.source);
  return SimulatedSample{std::move(*setup), std::move(*errors), std::move(*simulated)};
}

PointSet SampleExportPoints(const SampleTruth& truth, const SimulatedSample& sample) {
  PointSet out = sample.simulated.points;
  if (truth.raw_scan) {
    out.feature.assign(out.size(), PointSet::kUnlabelled);
    out.feature_names.clear();
  }
  return out;
}

std::map<std::string, double> TruthValues(const kinematics::ErrorState& errors,
                                          const std::vector<std::string>& coefficient_names) {
  std::map<std::string, double> out;
  for (const auto& name : coefficient_names) {
    if (auto i = errors.FindCoefficient(name)) {
      out[name] = errors.coefficient(*i) * errors.coefficient_info(*i).display_per_internal;
    } else {
      out[name] = 0.0;
    }
  }
  return out;
}

Result<std::map<std::string, double>> LoadTruthValues(const std::string& truth_path,
                                                      const std::vector<std::string>& coefficient_names) {
  auto truth = LoadSampleTruth(truth_path);
  if (!truth.ok()) return truth.status();
  auto setup = LoadPiece({.testpiece = truth->testpiece, .machine_path = truth->machine, .allow_piece_file = true});
  if (!setup.ok()) return setup.status();
  auto errors = kinematics::ParseErrorState(truth->errors_yaml, truth->source + " (errors)", setup->machine);
  if (!errors.ok()) return errors.status();
  return TruthValues(*errors, coefficient_names);
}

}  // namespace tpcal::pipeline
