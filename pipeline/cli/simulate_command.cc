// tpcal simulate --testpiece NAME --machine M.yaml --errors E.yaml [--process P.yaml] [--config TP.yaml]
//                [--density ...] [--noise-um S] [--seed N] [--placement datum|random]
//                [--probe-radius-error-um R] -o POINTS.csv [--truth TRUTH.yaml]
// tpcal simulate --instrument datum_ball [--machine M.yaml] --errors E.yaml [--noise-um S] [--seed N]
//                [--tilt-deg T,...] [--c-step-deg D] [--ball X,Y,Z] [--seconds-per-position S]
//                -o BALLPOS.csv [--truth TRUTH.yaml]
// tpcal simulate --instrument probe_artifacts [--machine M.yaml] --errors E.yaml [--artifacts A.yaml]
//                [--noise-um S] [--seed N] [--tilt-deg A,...] [--c-step-deg D] [--probe-radius-mm R]
//                [--pretravel-um P0] [--pretravel-lobing-um P3] [--seconds-per-touch S]
//                -o PROBEPTS.csv [--truth TRUTH.yaml]
// tpcal simulate --instrument ballbar --setup S.yaml [--machine M.yaml] --errors E.yaml [--noise-um S]
//                [--seed N] [--angles-deg A,... | --step-deg D] [--seconds-per-reading S]
//                -o BALLBAR.csv [--truth TRUTH.yaml]
//
// Virtual machining and measurement of a test piece (pipeline/simulate_stage.h): a `tpcal points
// v1` CSV (docs/formats/points.md); or the virtual datum-ball instrument
// (pipeline/datum_ball_simulate_stage.h): a `tpcal ballpos v1` CSV (docs/formats/ballpos.md); or
// the virtual probing test of artifacts (pipeline/probe_artifacts_simulate_stage.h): a `tpcal
// probepts v1` CSV (docs/formats/probepts.md); or the virtual double ball bar
// (pipeline/ballbar_simulate_stage.h): a `tpcal ballbar v1` CSV (docs/formats/ballbar.md).
// Optionally the stated truth.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "pipeline/ballbar_simulate_stage.h"
#include "pipeline/cli/ball_option.h"
#include "pipeline/cli/commands.h"
#include "pipeline/cli/piece_args.h"
#include "pipeline/datum_ball_simulate_stage.h"
#include "pipeline/io/atomic_file.h"
#include "pipeline/probe_artifacts_simulate_stage.h"
#include "pipeline/simulate_stage.h"

namespace tpcal::cli {
namespace {

struct SimulateArgs {
  PieceArgs piece;
  pipeline::SimulateRequest request;
  std::string out;
  std::string truth;
  std::string instrument;  // "" = a test piece; datum_ball; probe_artifacts
  std::vector<double> tilt_deg, ball_mm;
  std::optional<double> c_step_deg;
  double seconds_per_position = 60.0;
  // probe_artifacts only
  std::string artifacts;
  kinematics::TouchOptions touch;
  double seconds_per_touch = 10.0;
  // ballbar only
  std::string setup;
  pipeline::BallbarAngles bar_angles;
  double seconds_per_reading = 5.0;
};

// Options of one path given on the other: their names, for the message.
const char* const kPieceOnly[] = {"--config", "--density", "--levels", "--process", "--placement",
                                  "--max-translation-mm", "--probe-radius-error-um"};
const char* const kBallOnly[] = {"--ball", "--seconds-per-position"};
const char* const kProbeOnly[] = {"--artifacts", "--probe-radius-mm", "--pretravel-um", "--pretravel-lobing-um",
                                  "--seconds-per-touch"};
const char* const kInstrumentOnly[] = {"--tilt-deg", "--c-step-deg"};  // datum_ball, probe_artifacts
const char* const kBarOnly[] = {"--setup", "--angles-deg", "--step-deg", "--seconds-per-reading"};

Status CheckPathOptions(const CLI::App& sub, const SimulateArgs& args) {
  const bool instrument = !args.instrument.empty();
  const bool ball = args.instrument == "datum_ball";
  const bool bar = args.instrument == "ballbar";
  if (instrument && !args.piece.testpiece.empty())
    return Status(StatusCode::kInvalidArgument,
                  "--testpiece and --instrument: give one (a test piece to machine and measure, or an instrument)");
  if (!instrument && args.piece.testpiece.empty())
    return Status(StatusCode::kInvalidArgument,
                  "--testpiece NAME (or --instrument datum_ball, probe_artifacts or ballbar) is required");
  if (!instrument && args.piece.machine.empty())
    return Status(StatusCode::kInvalidArgument, "--machine is required with --testpiece");
  auto named = [&](std::span<const char* const> names) -> const char* {
    for (const char* name : names)
      if (sub.count(name) > 0) return name;
    return nullptr;
  };
  if (instrument) {
    if (const char* n = named(kPieceOnly))
      return Status(StatusCode::kInvalidArgument,
                    std::string(n) + " is a test-piece option, not one of --instrument " + args.instrument);
    for (std::span<const char* const> other :
         bar ? std::vector<std::span<const char* const>>{kBallOnly, kProbeOnly, kInstrumentOnly}
             : std::vector<std::span<const char* const>>{ball ? std::span<const char* const>(kProbeOnly)
                                                               : std::span<const char* const>(kBallOnly),
                                                          kBarOnly}) {
      if (const char* n = named(other))
        return Status(StatusCode::kInvalidArgument,
                      std::string(n) + " is not an option of --instrument " + args.instrument);
    }
  } else {
    if (const char* n = named(kInstrumentOnly))
      return Status(StatusCode::kInvalidArgument, std::string(n) + " needs --instrument datum_ball or probe_artifacts");
    if (const char* n = named(kBallOnly))
      return Status(StatusCode::kInvalidArgument, std::string(n) + " needs --instrument datum_ball");
    if (const char* n = named(kProbeOnly))
      return Status(StatusCode::kInvalidArgument, std::string(n) + " needs --instrument probe_artifacts");
    if (const char* n = named(kBarOnly))
      return Status(StatusCode::kInvalidArgument, std::string(n) + " needs --instrument ballbar");
  }
  if (ball) {
    auto b = BallOption(args.ball_mm);
    if (!b.ok()) return b.status();
  }
  return Status::Ok();
}

int RunDatumBallSimulate(const SimulateArgs& args) {
  pipeline::DatumBallSimRequest request;
  request.machine_path = args.piece.machine;
  request.errors_path = args.request.errors_path;
  request.output_path = args.out;
  if (!args.tilt_deg.empty()) request.plan.tilt_deg = args.tilt_deg;
  if (args.c_step_deg) request.plan.c_step_deg = *args.c_step_deg;
  if (auto b = BallOption(args.ball_mm); b.ok() && b->has_value()) request.plan.ball_part_mm = **b;
  request.noise_um = args.request.noise_um;
  request.seed = args.request.seed;
  request.seconds_per_position = args.seconds_per_position;
  request.truth = !args.truth.empty();
  auto sim = pipeline::RunDatumBallSimulateStage(request);
  if (!sim.ok()) return ReportError(sim.status());
  if (Status s = pipeline::WriteFileAtomic(args.out, sim->csv); !s.ok()) return ReportError(s);
  Info(fmt::format("wrote {}: {} datum-ball readings (noise {} um, seed {}{})", args.out, sim->readings.size(),
                   request.noise_um, request.seed, sim->timed ? ", with t_s: the errors have thermal terms" : ""));
  if (!args.truth.empty()) {
    if (Status s = pipeline::WriteFileAtomic(args.truth, sim->truth_yaml); !s.ok()) return ReportError(s);
    Info("wrote " + args.truth);
  }
  return kExitOk;
}

int RunProbeArtifactsSimulate(const SimulateArgs& args) {
  pipeline::ProbeArtifactsSimRequest request;
  request.machine_path = args.piece.machine;
  request.errors_path = args.request.errors_path;
  request.artifacts_path = args.artifacts;
  request.output_path = args.out;
  if (!args.tilt_deg.empty()) request.plan.a_deg = args.tilt_deg;
  if (args.c_step_deg) request.plan.c_step_deg = *args.c_step_deg;
  request.touch = args.touch;
  request.noise_um = args.request.noise_um;
  request.seed = args.request.seed;
  request.seconds_per_touch = args.seconds_per_touch;
  request.truth = !args.truth.empty();
  auto sim = pipeline::RunProbeArtifactsSimulateStage(request);
  if (!sim.ok()) return ReportError(sim.status());
  if (Status s = pipeline::WriteFileAtomic(args.out, sim->csv); !s.ok()) return ReportError(s);
  Info(fmt::format("wrote {}: {} touches at {} poses, {} planned out (noise {} um, seed {}, pre-travel {} um + {} um "
                   "lobing{})",
                   args.out, sim->touches.size(), sim->plan.poses.size(), sim->plan.skipped.size(), request.noise_um,
                   request.seed, request.touch.pretravel_um, request.touch.pretravel_lobing_um,
                   sim->timed ? ", with t_s: the errors have thermal terms" : ""));
  if (!args.truth.empty()) {
    if (Status s = pipeline::WriteFileAtomic(args.truth, sim->truth_yaml); !s.ok()) return ReportError(s);
    Info("wrote " + args.truth);
  }
  return kExitOk;
}

int RunBallbarSimulate(const SimulateArgs& args) {
  pipeline::BallbarSimRequest request;
  request.setup_path = args.setup;
  request.machine_path = args.piece.machine;
  request.errors_path = args.request.errors_path;
  request.output_path = args.out;
  request.angles = args.bar_angles;
  request.noise_um = args.request.noise_um;
  request.seed = args.request.seed;
  request.seconds_per_reading = args.seconds_per_reading;
  request.truth = !args.truth.empty();
  auto sim = pipeline::RunBallbarSimulateStage(request);
  if (!sim.ok()) return ReportError(sim.status());
  if (Status s = pipeline::WriteFileAtomic(args.out, sim->csv); !s.ok()) return ReportError(s);
  Info(fmt::format("wrote {}: {} ball-bar readings of {} installations (noise {} um, seed {}{})", args.out,
                   sim->file.rows.size(), sim->tests.size(), request.noise_um, request.seed,
                   sim->timed ? ", with t_s: the errors have thermal terms" : ""));
  if (!args.truth.empty()) {
    if (Status s = pipeline::WriteFileAtomic(args.truth, sim->truth_yaml); !s.ok()) return ReportError(s);
    Info("wrote " + args.truth);
  }
  return kExitOk;
}

int RunSimulate(const CLI::App& sub, const SimulateArgs& args) {
  if (Status s = CheckPathOptions(sub, args); !s.ok()) return ReportError(s);
  if (!args.instrument.empty()) {
    if (Status s = CheckDistinctOutputs({{"-o", args.out}, {"--truth", args.truth}}); !s.ok()) return ReportError(s);
    if (args.instrument == "ballbar") return RunBallbarSimulate(args);
    return args.instrument == "probe_artifacts" ? RunProbeArtifactsSimulate(args) : RunDatumBallSimulate(args);
  }
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
      "with --truth, a YAML of the placement (cmm_from_part), the errors, noise, seed and per-feature deviations.\n"
      "With --instrument datum_ball instead of --testpiece: the virtual datum-ball test (seed 001): at each rotary\n"
      "position the linear commands centring the probe on a ball on the table, solved through the full chain with\n"
      "the errors (thermal terms at t_s = reading index x --seconds-per-position), plus Gaussian noise per\n"
      "coordinate; writes a tpcal ballpos v1 CSV for `tpcal identify --instrument datum_ball`.\n"
      "With --instrument probe_artifacts: the virtual on-machine probing test of artifacts (seed 000): every touch\n"
      "of the plan (`tpcal plan --instrument probe_artifacts`) solved through the full chain with the errors\n"
      "(thermal terms at t_s = touch index x --seconds-per-touch), the stylus pre-travel added along the approach,\n"
      "plus Gaussian noise along the approach; writes a tpcal probepts v1 CSV (contact x,y,z in mm to 0.1 um and\n"
      "approach i,j,k, machine frame).\n"
      "With --instrument ballbar: the virtual double ball bar (seed 003; ISO 230-4 circular tests): every reading of\n"
      "the plan (`tpcal plan --instrument ballbar`: the --setup installations at their angles) is the bar-length\n"
      "change through the full chain with the errors (thermal terms at t_s = reading index x --seconds-per-reading)\n"
      "plus Gaussian noise, rounded to 0.1 um; writes a tpcal ballbar v1 CSV (setup, angle_deg, dl_um).");
  AddPieceOptions(sub, &args->piece, /*machine_required=*/true);
  // Required on the test-piece path only (checked in RunSimulate).
  sub->get_option("--testpiece")->required(false);
  sub->get_option("--machine")->required(false)->description(
      "machine model YAML (schema tpcal.machine/1, samples/machines/); required with --testpiece; "
      "--instrument datum_ball: default the nominal bc_table; --instrument probe_artifacts: an A/C table, default "
      "the nominal ac_table; --instrument ballbar: default the nominal bhead_ctable");
  sub->add_option("--instrument", args->instrument,
                  "datum_ball, probe_artifacts or ballbar: simulate that instrument instead of a test piece (not with "
                  "--testpiece)")
      ->check(CLI::IsMember({"datum_ball", "probe_artifacts", "ballbar"}));
  sub->add_option("--setup", args->setup,
                  "ballbar: the installations, YAML (schema tpcal.ballbar_setup/1, docs/formats/ballbar_setup.md; "
                  "mm), e.g. samples/ballbar/seed003_setups.yaml; required with --instrument ballbar");
  sub->add_option("--angles-deg", args->bar_angles.angles_deg,
                  "ballbar: the angles of every installation, deg (default C 0..360 every 20, A or B 0..-100 every "
                  "5, circles 0..359 every 1, ccw then cw)")
      ->delimiter(',');
  sub->add_option("--step-deg", args->bar_angles.step_deg, "ballbar: the default ranges in this step, deg");
  sub->add_option("--seconds-per-reading", args->seconds_per_reading,
                  "ballbar: time between readings, s (t_s of reading i = i x this; only when the errors have thermal "
                  "terms)")
      ->capture_default_str();
  sub->add_option("--tilt-deg", args->tilt_deg,
                  "datum_ball: tilt-axis (B or A) commands, deg (default 0,30,-30); probe_artifacts: A commands, deg "
                  "(default 0,-30,-60,-90)")
      ->delimiter(',');
  sub->add_option("--c-step-deg", args->c_step_deg,
                  "C from 0 to < 360 deg in this step, deg (default 30 datum_ball, 60 probe_artifacts)");
  sub->add_option("--ball", args->ball_mm, "datum_ball: nominal ball centre X,Y,Z, mm, part frame (default 200,0.1,300)")
      ->delimiter(',');
  sub->add_option("--seconds-per-position", args->seconds_per_position,
                  "datum_ball: time between readings, s (t_s of reading i = i x this; only when the errors have "
                  "thermal terms)")
      ->capture_default_str();
  sub->add_option("--artifacts", args->artifacts,
                  "probe_artifacts: the artifact boxes, YAML (schema tpcal.artifacts/1, docs/formats/artifacts.md; part "
                  "frame, mm); default: seed 000's three 30 x 30 x 60 mm columns");
  sub->add_option("--probe-radius-mm", args->touch.probe_radius_mm, "probe_artifacts: stylus ball radius, mm")
      ->capture_default_str();
  sub->add_option("--pretravel-um", args->touch.pretravel_um,
                  "probe_artifacts: uncompensated constant pre-travel p0 of the touch-trigger probe, um (each reading "
                  "moves p0 along its approach)")
      ->capture_default_str();
  sub->add_option("--pretravel-lobing-um", args->touch.pretravel_lobing_um,
                  "probe_artifacts: three-lobed pre-travel amplitude p3, um: p3 |d_xy| cos(3 phi) along the approach d, "
                  "phi its azimuth in machine XY (kinematics/probe_touch.h)")
      ->capture_default_str();
  sub->add_option("--seconds-per-touch", args->seconds_per_touch,
                  "probe_artifacts: time between touches, s (t_s of touch i = i x this; only when the errors have "
                  "thermal terms)")
      ->capture_default_str();
  sub->add_option("--errors", args->request.errors_path,
                  "machine error YAML (schema tpcal.errors/1, kinematics/errors_yaml.md): E_X0C_um: 10, "
                  "E_B0C_urad: -20, dx_CR(0)_um: 12.4, effects: [...]; unknown keys are errors")
      ->required();
  sub->add_option("--process", args->request.process_path,
                  "process effects YAML (schema tpcal.process/1, testpieces/process_effects_yaml.h): tool_deflection "
                  "{compliance_um_per_n: [x, y, z], ...}, servo_reversal {spike_x_um, spike_y_um, decay_deg, "
                  "backlash_x_um, backlash_y_um}; default none");
  sub->add_option("--noise-um", args->request.noise_um,
                  "1-sigma CMM probing noise along the normal, um (datum_ball: of each coordinate of a reading; "
                  "probe_artifacts: of each contact along its approach; ballbar: of each bar reading dl)")
      ->capture_default_str();
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
  sub->add_option("-o,--output", args->out,
                  "point CSV to write (docs/formats/points.md); datum_ball: ball-position CSV (docs/formats/ballpos.md); "
                  "probe_artifacts: probed-point CSV (docs/formats/probepts.md); ballbar: ball-bar CSV "
                  "(docs/formats/ballbar.md)")
      ->required();
  sub->add_option("--truth", args->truth, "also write the stated truth as YAML (schema tpcal.simulation_truth/1)");
  return {sub, [args, sub] { return RunSimulate(*sub, *args); }};
}

}  // namespace tpcal::cli
