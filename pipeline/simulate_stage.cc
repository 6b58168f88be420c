#include "pipeline/simulate_stage.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "core/units.h"
#include "kinematics/errors_yaml.h"
#include "pipeline/io/point_io.h"
#include "pipeline/truth_yaml_text.h"
#include "testpieces/piece_config.h"
#include "testpieces/process_effects_yaml.h"

namespace tpcal::pipeline {
namespace {

std::string RigidYaml(const Rigid3& t) {
  const Eigen::Matrix3d r = t.linear();
  const Eigen::Vector3d p = t.translation();
  std::string out = "\n    rotation:  # row-major 3x3\n";
  for (int i = 0; i < 3; ++i)
    out += fmt::format("      - [{}, {}, {}]\n", TruthNum(r(i, 0)), TruthNum(r(i, 1)), TruthNum(r(i, 2)));
  out += fmt::format("    translation_mm: [{}, {}, {}]\n", TruthNum(p.x()), TruthNum(p.y()), TruthNum(p.z()));
  return out;
}

// The stated truth of a simulated measurement (schema tpcal.simulation_truth/1).
std::string TruthYaml(const SimulateRequest& args, const LoadedPiece& built, const kinematics::ErrorState& errors,
                      const testpieces::ProcessEffects& process, const testpieces::SimulatedPiece& sim) {
  const testpieces::TestPiece& piece = built.piece;
  std::string y;
  y += "# Stated truth of a tpcal simulate run: what was cut, by which machine errors, and how it was\n";
  y += "# measured. Frames: p_in_cmm = cmm_from_part * p_in_part (part = table frame of the machine);\n";
  y += "# cmm_from_datum = cmm_from_part * part_from_datum (the datum frame of the plan CSV).\n";
  y += "schema: tpcal.simulation_truth/1\n";
  y += "testpiece: " + TruthStr(args.testpiece) + "\n";
  y += "piece_name: " + TruthStr(piece.name) + "\n";
  y += "config: " + TruthStr(args.config_path) + "  # empty: the piece's defaults (effective values below)\n";
  y += "machine_file: " + TruthStr(args.machine_path) + "\n";
  y += std::string("machine_type: ") + kinematics::MachineTypeName(built.machine.type) + "\n";
  y += "errors_file: " + TruthStr(args.errors_path) + "\n";
  y += "points_file: " + TruthStr(args.points_path) + "\n";
  y += fmt::format("n_points: {}\n", sim.points.size());
  y += fmt::format("seed: {}  # std::mt19937_64: placement first, then one normal deviate per point\n", args.seed);
  y += "noise_um: " + TruthNum(args.noise_um) + "  # 1-sigma CMM noise along the normal\n";
  y += "probe_radius_error_um: " + TruthNum(args.probe_radius_error_um) + "  # actual - calibrated probe radius\n";
  y += "placement: " + args.placement + "\n";
  if (args.placement == "random") y += "max_translation_mm: " + TruthNum(args.max_translation_mm) + "\n";
  y += "cmm_from_part:" + RigidYaml(sim.truth.cmm_from_part);
  y += "cmm_from_datum:" + RigidYaml(sim.truth.cmm_from_part * piece.part_from_datum);
  y += "part_from_datum:" + RigidYaml(piece.part_from_datum);

  // Machined deviation (actual - nominal along the outward normal, before the CMM) per feature.
  struct Stats { std::size_t n = 0; double min = INFINITY, max = -INFINITY, sum = 0, sum2 = 0; };
  std::vector<std::string> order;
  std::map<std::string, Stats> by_feature;
  const auto& plan_points = sim.truth.plan.points;
  for (std::size_t i = 0; i < plan_points.size(); ++i) {
    const std::string& f = plan_points[i].feature;
    if (!by_feature.count(f)) order.push_back(f);
    Stats& s = by_feature[f];
    const double d_um = MmToUm(sim.truth.deviation_mm[i]);
    ++s.n;
    s.min = std::min(s.min, d_um);
    s.max = std::max(s.max, d_um);
    s.sum += d_um;
    s.sum2 += d_um * d_um;
  }
  y += "# Machined surface deviation per feature (um, + = material left outward), before CMM noise.\n";
  y += "deviation_by_feature:\n";
  for (const std::string& f : order) {
    const Stats& s = by_feature[f];
    y += fmt::format("  {}: {{n: {}, mean_um: {}, min_um: {}, max_um: {}, rms_um: {}}}\n", TruthStr(f), s.n,
                     TruthNum(s.sum / s.n), TruthNum(s.min), TruthNum(s.max), TruthNum(std::sqrt(s.sum2 / s.n)));
  }
  y += "errors:\n" + IndentLines(kinematics::FormatErrorState(errors, built.machine), "  ");
  y += "process_file: " + TruthStr(args.process_path) + "\n";
  y += "process:  # tool deflection and servo reversal (tpcal.process/1); {} = none\n" +
       IndentLines(testpieces::FormatProcessEffects(process), "  ");
  y += "testpiece_config:\n" + IndentLines(testpieces::FormatPieceConfig(piece.config), "  ");
  return y;
}

}  // namespace

Status SimulateRequest::Validate() const {
  if (!(noise_um >= 0) || !std::isfinite(noise_um))
    return Status(StatusCode::kInvalidArgument, "--noise-um must be a finite number >= 0 (um)");
  if (!std::isfinite(probe_radius_error_um))
    return Status(StatusCode::kInvalidArgument, "--probe-radius-error-um must be finite (um)");
  if (!(max_translation_mm >= 0) || !std::isfinite(max_translation_mm))
    return Status(StatusCode::kInvalidArgument, "--max-translation-mm must be a finite number >= 0");
  return Status::Ok();
}

Result<SimulateStageResult> RunSimulateStage(const LoadedPiece& loaded, const SimulateRequest& request) {
  auto info = [&](const std::string& line) {
    if (request.info) request.info(line);
  };
  auto errors = kinematics::LoadErrorState(request.errors_path, loaded.machine);
  if (!errors.ok())
    return errors.status().file().empty() ? errors.status().WithLocation(request.errors_path) : errors.status();
  testpieces::ProcessEffects process;
  if (!request.process_path.empty()) {
    auto read = testpieces::LoadProcessEffects(request.process_path);
    if (!read.ok()) return read.status();
    process = std::move(*read);
  }

  testpieces::PieceSimOptions options;
  options.process = process;
  options.noise_um = request.noise_um;
  options.seed = request.seed;
  options.probe_radius_error_um = request.probe_radius_error_um;
  options.random_placement = request.placement == "random";
  options.max_translation_mm = request.max_translation_mm;
  info(fmt::format("tpcal simulate: {} on {} with {} error terms from {}, {:.1f} min of machining", loaded.piece.name,
                   kinematics::MachineTypeName(loaded.machine.type), errors->terms().size(), request.errors_path,
                   loaded.piece.duration_s() / 60.0));
  auto sim = testpieces::SimulatePiece(loaded.piece, loaded.machine, *errors, options);
  if (!sim.ok()) return kinematics::AtErrorsFile(sim.status().WithContext("simulating " + loaded.piece.name), request.errors_path);
  info(fmt::format("simulated {} points: CMM noise {} um (seed {}), probe radius error {} um, placement {}{}{}",
                   sim->points.size(), request.noise_um, request.seed, request.probe_radius_error_um,
                   request.placement, process.deflection ? ", tool deflection" : "",
                   process.servo ? ", servo reversal" : ""));

  for (Eigen::Vector3d& n : sim->points.normal) n = n.array() + 0.0;  // no "-0" in the file
  auto text = FormatPointCsv(sim->points);
  if (!text.ok()) return text.status().WithLocation(request.points_path);
  SimulateStageResult out;
  if (request.truth) out.truth_yaml = TruthYaml(request, loaded, *errors, process, *sim);
  out.csv = std::move(*text);
  out.simulated = std::move(*sim);
  return out;
}

}  // namespace tpcal::pipeline
