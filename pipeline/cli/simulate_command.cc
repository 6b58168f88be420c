// tpcal simulate --testpiece NAME --machine M.yaml --errors E.yaml [--process P.yaml] [--config TP.yaml]
//                [--density ...] [--noise-um S] [--seed N] [--placement datum|random]
//                [--probe-radius-error-um R] -o POINTS.csv [--truth TRUTH.yaml]
//
// Virtual machining and measurement of a test piece (testpieces::SimulatePiece): every probing-
// plan point solved on the surface the erroneous machine actually cut, then measured by a
// virtual CMM (noise along the normal, probe-radius error, optional random placement). Writes
// a `tpcal points v1` CSV (docs/formats/points.md) and, optionally, the stated truth.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/units.h"
#include "kinematics/errors_yaml.h"
#include "pipeline/io/atomic_file.h"
#include "pipeline/cli/commands.h"
#include "pipeline/cli/piece_args.h"
#include "pipeline/io/point_io.h"
#include "testpieces/piece_config.h"
#include "testpieces/process_effects_yaml.h"
#include "testpieces/simulate_piece.h"

namespace tpcal::cli {
namespace {

struct SimulateArgs {
  PieceArgs piece;
  std::string errors;
  std::string process;  // tpcal.process/1 YAML: tool deflection, servo reversal
  double noise_um = 0.0;
  std::uint64_t seed = 1;
  std::string placement = "datum";
  double max_translation_mm = 300.0;
  double probe_radius_error_um = 0.0;
  std::string out;
  std::string truth;
};

std::string Num(double v) { return fmt::format("{:.17g}", v == 0.0 ? 0.0 : v); }

// A YAML flow string, quoted when it could be read as something else.
std::string Str(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out.push_back('\\');
    out.push_back(c);
  }
  return out + "\"";
}

std::string Indent(const std::string& text, const std::string& pad) {
  std::istringstream in(text);
  std::string line, out;
  while (std::getline(in, line)) out += line.empty() ? "\n" : pad + line + "\n";
  return out;
}

std::string RigidYaml(const Rigid3& t) {
  const Eigen::Matrix3d r = t.linear();
  const Eigen::Vector3d p = t.translation();
  std::string out = "\n    rotation:  # row-major 3x3\n";
  for (int i = 0; i < 3; ++i) out += fmt::format("      - [{}, {}, {}]\n", Num(r(i, 0)), Num(r(i, 1)), Num(r(i, 2)));
  out += fmt::format("    translation_mm: [{}, {}, {}]\n", Num(p.x()), Num(p.y()), Num(p.z()));
  return out;
}

// The stated truth of a simulated measurement (schema tpcal.simulation_truth/1).
std::string TruthYaml(const SimulateArgs& args, const pipeline::LoadedPiece& built, const kinematics::ErrorState& errors,
                      const testpieces::ProcessEffects& process, const testpieces::SimulatedPiece& sim) {
  const testpieces::TestPiece& piece = built.piece;
  std::string y;
  y += "# Stated truth of a tpcal simulate run: what was cut, by which machine errors, and how it was\n";
  y += "# measured. Frames: p_in_cmm = cmm_from_part * p_in_part (part = table frame of the machine);\n";
  y += "# cmm_from_datum = cmm_from_part * part_from_datum (the datum frame of the plan CSV).\n";
  y += "schema: tpcal.simulation_truth/1\n";
  y += "testpiece: " + Str(args.piece.testpiece) + "\n";
  y += "piece_name: " + Str(piece.name) + "\n";
  y += "config: " + Str(args.piece.config) + "  # empty: the piece's defaults (effective values below)\n";
  y += "machine_file: " + Str(args.piece.machine) + "\n";
  y += std::string("machine_type: ") + kinematics::MachineTypeName(built.machine.type) + "\n";
  y += "errors_file: " + Str(args.errors) + "\n";
  y += "points_file: " + Str(args.out) + "\n";
  y += fmt::format("n_points: {}\n", sim.points.size());
  y += fmt::format("seed: {}  # std::mt19937_64: placement first, then one normal deviate per point\n", args.seed);
  y += "noise_um: " + Num(args.noise_um) + "  # 1-sigma CMM noise along the normal\n";
  y += "probe_radius_error_um: " + Num(args.probe_radius_error_um) + "  # actual - calibrated probe radius\n";
  y += "placement: " + args.placement + "\n";
  if (args.placement == "random") y += "max_translation_mm: " + Num(args.max_translation_mm) + "\n";
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
    y += fmt::format("  {}: {{n: {}, mean_um: {}, min_um: {}, max_um: {}, rms_um: {}}}\n", Str(f), s.n,
                     Num(s.sum / s.n), Num(s.min), Num(s.max), Num(std::sqrt(s.sum2 / s.n)));
  }
  y += "errors:\n" + Indent(kinematics::FormatErrorState(errors, built.machine), "  ");
  y += "process_file: " + Str(args.process) + "\n";
  y += "process:  # tool deflection and servo reversal (tpcal.process/1); {} = none\n" +
       Indent(testpieces::FormatProcessEffects(process), "  ");
  y += "testpiece_config:\n" + Indent(testpieces::FormatPieceConfig(piece.config), "  ");
  return y;
}

int RunSimulate(const SimulateArgs& args) {
  // Everything is read and checked before anything is written.
  if (Status s = CheckDistinctOutputs({{"-o", args.out}, {"--truth", args.truth}}); !s.ok()) return ReportError(s);
  if (!(args.noise_um >= 0) || !std::isfinite(args.noise_um))
    return ReportError(Status(StatusCode::kInvalidArgument, "--noise-um must be a finite number >= 0 (um)"));
  if (!std::isfinite(args.probe_radius_error_um))
    return ReportError(Status(StatusCode::kInvalidArgument, "--probe-radius-error-um must be finite (um)"));
  if (!(args.max_translation_mm >= 0) || !std::isfinite(args.max_translation_mm))
    return ReportError(Status(StatusCode::kInvalidArgument, "--max-translation-mm must be a finite number >= 0"));
  auto built = BuildPiece(args.piece);
  if (!built.ok()) return ReportError(built.status());
  auto errors = kinematics::LoadErrorState(args.errors, built->machine);
  if (!errors.ok())
    return ReportError(errors.status().file().empty() ? errors.status().WithLocation(args.errors) : errors.status());

  testpieces::ProcessEffects process;
  if (!args.process.empty()) {
    auto loaded = testpieces::LoadProcessEffects(args.process);
    if (!loaded.ok()) return ReportError(loaded.status());
    process = std::move(*loaded);
  }

  testpieces::PieceSimOptions options;
  options.process = process;
  options.noise_um = args.noise_um;
  options.seed = args.seed;
  options.probe_radius_error_um = args.probe_radius_error_um;
  options.random_placement = args.placement == "random";
  options.max_translation_mm = args.max_translation_mm;
  Info(fmt::format("tpcal simulate: {} on {} with {} error terms from {}, {:.1f} min of machining",
                   built->piece.name, kinematics::MachineTypeName(built->machine.type), errors->terms().size(),
                   args.errors, built->piece.duration_s() / 60.0));
  auto sim = testpieces::SimulatePiece(built->piece, built->machine, *errors, options);
  if (!sim.ok()) return ReportError(sim.status().WithContext("simulating " + built->piece.name));
  Info(fmt::format("simulated {} points: CMM noise {} um (seed {}), probe radius error {} um, placement {}{}{}",
                   sim->points.size(), args.noise_um, args.seed, args.probe_radius_error_um, args.placement,
                   process.deflection ? ", tool deflection" : "", process.servo ? ", servo reversal" : ""));

  for (Eigen::Vector3d& n : sim->points.normal) n = n.array() + 0.0;  // no "-0" in the file
  auto text = pipeline::FormatPointCsv(sim->points);
  if (!text.ok()) return ReportError(text.status().WithLocation(args.out));
  std::string truth;
  if (!args.truth.empty()) truth = TruthYaml(args, *built, *errors, process, *sim);

  if (Status s = pipeline::WriteFileAtomic(args.out, *text); !s.ok()) return ReportError(s);
  Info(fmt::format("wrote {}: {} points on {} features (CMM frame, mm)", args.out, sim->points.size(),
                   sim->points.feature_names.size()));
  if (!args.truth.empty()) {
    if (Status s = pipeline::WriteFileAtomic(args.truth, truth); !s.ok()) return ReportError(s);
    Info("wrote " + args.truth);
  }
  return kExitOk;
}

}  // namespace

Command RegisterSimulate(CLI::App& app) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* sub = app.add_subcommand(
      "simulate",
      "Virtually machine a test piece with machine errors and measure it with a virtual CMM.\n"
      "Every probing-plan point is solved on the surface the machine actually cut (full kinematic chain with\n"
      "the errors at the axis state, time and operation of its cut), then measured: CMM noise along the normal,\n"
      "probe-radius error, and the part placed on the CMM (datum: CMM frame = the part's datum frame; random:\n"
      "a random rigid placement). Writes a tpcal points v1 CSV (feature,x,y,z,i,j,k in mm, CMM frame) and,\n"
      "with --truth, a YAML of the placement (cmm_from_part), the errors, noise, seed and per-feature deviations.");
  AddPieceOptions(sub, &args->piece, /*machine_required=*/true);
  sub->add_option("--errors", args->errors,
                  "machine error YAML (schema tpcal.errors/1, kinematics/errors_yaml.md): E_X0C_um: 10, "
                  "E_B0C_urad: -20, dx_CR(0)_um: 12.4, effects: [...]; unknown keys are errors")
      ->required();
  sub->add_option("--process", args->process,
                  "process effects YAML (schema tpcal.process/1, testpieces/process_effects_yaml.h): tool_deflection "
                  "{compliance_um_per_n: [x, y, z], ...}, servo_reversal {spike_x_um, spike_y_um, decay_deg, "
                  "backlash_x_um, backlash_y_um}; default none");
  sub->add_option("--noise-um", args->noise_um, "1-sigma CMM probing noise along the normal, um")->capture_default_str();
  sub->add_option("--seed", args->seed, "seed of std::mt19937_64 (placement, then noise)")->capture_default_str();
  sub->add_option("--placement", args->placement,
                  "part on the CMM: datum (CMM frame = nominal datum frame) or random (uniform rotation, translation "
                  "within +-max-translation-mm per axis)")
      ->check(CLI::IsMember({"datum", "random"}))
      ->capture_default_str();
  sub->add_option("--max-translation-mm", args->max_translation_mm, "random placement: translation bound per axis, mm")
      ->capture_default_str();
  sub->add_option("--probe-radius-error-um", args->probe_radius_error_um,
                  "actual minus calibrated probe radius, um (every point moves outward along its normal)")
      ->capture_default_str();
  sub->add_option("-o,--output", args->out, "point CSV to write (docs/formats/points.md)")->required();
  sub->add_option("--truth", args->truth, "also write the stated truth as YAML (schema tpcal.simulation_truth/1)");
  return {sub, [args] { return RunSimulate(*args); }};
}

}  // namespace tpcal::cli
