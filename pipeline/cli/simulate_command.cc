// tpcal simulate --testpiece NAME --machine M.yaml --errors E.yaml [--process P.yaml] [--config TP.yaml]
//                [--density ...] [--noise-um S] [--seed N] [--placement datum|random]
//                [--probe-radius-error-um R] -o POINTS.csv [--truth TRUTH.yaml]
//
// Virtual machining and measurement of a test piece (pipeline/simulate_stage.h). Writes a
// `tpcal points v1` CSV (docs/formats/points.md) and, optionally, the stated truth.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <memory>
#include <string>

#include "pipeline/cli/commands.h"
#include "pipeline/cli/piece_args.h"
#include "pipeline/io/atomic_file.h"
#include "pipeline/simulate_stage.h"

namespace tpcal::cli {
namespace {

struct SimulateArgs {
  PieceArgs piece;
  pipeline::SimulateRequest request;
  std::string out;
  std::string truth;
};

int RunSimulate(const SimulateArgs& args) {
  // Everything is read and checked before anything is written.
  if (Status s = CheckDistinctOutputs({{"-o", args.out}, {"--truth", args.truth}}); !s.ok()) return ReportError(s);
  if (Status s = args.request.Validate(); !s.ok()) return ReportError(s);
  auto built = BuildPiece(args.piece);
  if (!built.ok()) return ReportError(built.status());
  pipeline::SimulateRequest request = args.request;
  request.testpiece = args.piece.testpiece;
  request.config_path = args.piece.config;
  request.machine_path = args.piece.machine;
  request.points_path = args.out;
  request.truth = !args.truth.empty();
  request.info = Info;
  auto sim = pipeline::RunSimulateStage(*built, request);
  if (!sim.ok()) return ReportError(sim.status());

  if (Status s = pipeline::WriteFileAtomic(args.out, sim->csv); !s.ok()) return ReportError(s);
  Info(fmt::format("wrote {}: {} points on {} features (CMM frame, mm)", args.out, sim->simulated.points.size(),
                   sim->simulated.points.feature_names.size()));
  if (!args.truth.empty()) {
    if (Status s = pipeline::WriteFileAtomic(args.truth, sim->truth_yaml); !s.ok()) return ReportError(s);
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
  sub->add_option("--errors", args->request.errors_path,
                  "machine error YAML (schema tpcal.errors/1, kinematics/errors_yaml.md): E_X0C_um: 10, "
                  "E_B0C_urad: -20, dx_CR(0)_um: 12.4, effects: [...]; unknown keys are errors")
      ->required();
  sub->add_option("--process", args->request.process_path,
                  "process effects YAML (schema tpcal.process/1, testpieces/process_effects_yaml.h): tool_deflection "
                  "{compliance_um_per_n: [x, y, z], ...}, servo_reversal {spike_x_um, spike_y_um, decay_deg, "
                  "backlash_x_um, backlash_y_um}; default none");
  sub->add_option("--noise-um", args->request.noise_um, "1-sigma CMM probing noise along the normal, um")->capture_default_str();
  sub->add_option("--seed", args->request.seed, "seed of std::mt19937_64 (placement, then noise)")->capture_default_str();
  sub->add_option("--placement", args->request.placement,
                  "part on the CMM: datum (CMM frame = nominal datum frame) or random (uniform rotation, translation "
                  "within +-max-translation-mm per axis)")
      ->check(CLI::IsMember({"datum", "random"}))
      ->capture_default_str();
  sub->add_option("--max-translation-mm", args->request.max_translation_mm, "random placement: translation bound per axis, mm")
      ->capture_default_str();
  sub->add_option("--probe-radius-error-um", args->request.probe_radius_error_um,
                  "actual minus calibrated probe radius, um (every point moves outward along its normal)")
      ->capture_default_str();
  sub->add_option("-o,--output", args->out, "point CSV to write (docs/formats/points.md)")->required();
  sub->add_option("--truth", args->truth, "also write the stated truth as YAML (schema tpcal.simulation_truth/1)");
  return {sub, [args] { return RunSimulate(*args); }};
}

}  // namespace tpcal::cli
