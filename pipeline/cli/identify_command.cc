// tpcal identify POINTS --testpiece NAME [--config TP.yaml] [--machine M.yaml] [--anchor FEATURE@X,Y,Z]
//                [--uncertainty jackknife|analytic|mc|all] [--parameters P,...] [--json OUT]
//                tpcal identify BALLPOS --instrument datum_ball [--machine M.yaml] [--parameters P,...] [--ball X,Y,Z] [--json OUT]
//                tpcal identify PROBEPTS --instrument probe_artifacts [--artifacts A.yaml] [--machine M.yaml]
//                               [--probe-radius-mm R] [--json OUT]
//                tpcal identify BALLBAR --instrument ballbar --setup S.yaml [--machine M.yaml] [--json OUT] [--errors-out E.yaml]
#include <CLI/CLI.hpp>

#include <memory>
#include <optional>
#include <string>
#include <tuple>

#include "kinematics/error_parameters.h"
#include "pipeline/cli/anchor_option.h"
#include "pipeline/cli/column_option.h"
#include "pipeline/cli/commands.h"
#include "pipeline/cli/piece_args.h"
#include "pipeline/cli/ball_option.h"
#include "pipeline/ballbar_stage.h"
#include "pipeline/datum_ball_stage.h"
#include "pipeline/probe_artifacts_stage.h"
#include "pipeline/identify_report.h"
#include "pipeline/io/atomic_file.h"
#include "pipeline/report/identify_json.h"
#include "pipeline/report/identify_summary.h"
#include "testpieces/named_pieces.h"

namespace tpcal::cli {
namespace {

struct IdentifyArgs {
  pipeline::IdentifyRequest request;
  std::string anchor;  // FEATURE@X,Y,Z: the symmetric labelling of a raw scan
  std::string json;
  bool no_gap_check = false;
  std::string instrument;  // "" = a test piece; datum_ball = a ball-position file
  std::string errors_out;  // datum_ball: also the identified errors as tpcal.errors/1
  std::vector<double> ball_mm;  // datum_ball: the known ball centre (--ball X,Y,Z); empty = fitted
  std::string artifacts;   // probe_artifacts: the artifact YAML ("" = seed 000's three columns)
  std::string html;        // probe_artifacts: the page with the error-map figures
  std::vector<double> reference_pose_deg = {0.0, 0.0};  // probe_artifacts: A, C of the zero pose
  std::optional<double> probe_radius_mm;  // probe_artifacts: the stylus ball radius (default 3 mm)
  std::string setup;       // ballbar: the installations (tpcal.ballbar_setup/1)
};

int RunBallbar(const IdentifyArgs& args) {
  if (Status s = CheckDistinctOutputs({{"--json", args.json}, {"--errors-out", args.errors_out}}); !s.ok())
    return ReportError(s);
  auto report = pipeline::RunBallbarStage(
      {.path = args.request.points_path,
       .setup_path = args.setup,
       .machine_path = args.request.machine_path,
       .map_response_to = kinematics::LinearSquarenessSet()});
  if (!report.ok()) return ReportError(report.status());
  const int exit =
      WriteJsonOrText(args.json, pipeline::BallbarJson(*report), [&] { return pipeline::BallbarText(*report); });
  if (exit != kExitOk || args.errors_out.empty()) return exit;
  if (report->errors_yaml.empty()) {
    return ReportError(Status(StatusCode::kInvalidArgument,
                              "--errors-out: the test has no rotary installation, so no error tables to write"));
  }
  if (Status s = pipeline::WriteFileAtomic(args.errors_out, report->errors_yaml); !s.ok()) return ReportError(s);
  Info("wrote " + args.errors_out + " (tpcal.errors/1)");
  return kExitOk;
}

int RunProbeArtifacts(const IdentifyArgs& args) {
  if (Status s = CheckDistinctOutputs({{"--json", args.json}, {"--errors-out", args.errors_out}, {"--html", args.html}});
      !s.ok())
    return ReportError(s);
  if (args.reference_pose_deg.size() != 2) {
    return ReportError(Status(StatusCode::kInvalidArgument, "--reference-pose: expected A,C in degrees"));
  }
  pipeline::ProbeArtifactsRequest request;
  request.path = args.request.points_path;
  request.artifacts_path = args.artifacts;
  request.machine_path = args.request.machine_path;
  request.reference_a_deg = args.reference_pose_deg[0];
  request.reference_c_deg = args.reference_pose_deg[1];
  request.probe_radius_mm = args.probe_radius_mm.value_or(request.probe_radius_mm);
  auto report = pipeline::RunProbeArtifactsStage(request);
  if (!report.ok()) return ReportError(report.status());
  const int exit = WriteJsonOrText(args.json, pipeline::ProbeArtifactsJson(*report),
                                   [&] { return pipeline::ProbeArtifactsText(*report); });
  if (exit != kExitOk) return exit;
  for (const auto& [path, text, what] :
       {std::tuple{args.errors_out, report->errors_yaml, "tpcal.errors/1"},
        std::tuple{args.html, pipeline::ProbeArtifactsHtml(*report), "HTML"}}) {
    if (path.empty()) continue;
    if (Status s = pipeline::WriteFileAtomic(path, text); !s.ok()) return ReportError(s);
    Info("wrote " + path + " (" + what + ")");
  }
  return kExitOk;
}

int RunDatumBall(const IdentifyArgs& args) {
  if (Status s = CheckDistinctOutputs({{"--json", args.json}, {"--errors-out", args.errors_out}}); !s.ok())
    return ReportError(s);
  auto ball = BallOption(args.ball_mm);
  if (!ball.ok()) return ReportError(ball.status());
  auto report = pipeline::RunDatumBallStage({.path = args.request.points_path,
                                             .machine_path = args.request.machine_path,
                                             .parameters = args.request.parameters,
                                             .ball_part_mm = *ball});
  if (!report.ok()) return ReportError(report.status());
  const int exit =
      WriteJsonOrText(args.json, pipeline::DatumBallJson(*report), [&] { return pipeline::DatumBallText(*report); });
  if (exit != kExitOk || args.errors_out.empty()) return exit;
  if (Status s = pipeline::WriteFileAtomic(args.errors_out, report->errors_yaml); !s.ok()) return ReportError(s);
  Info("wrote " + args.errors_out + " (tpcal.errors/1)");
  return kExitOk;
}

int RunIdentify(const IdentifyArgs& args) {
  if (!args.setup.empty() && args.instrument != "ballbar")
    return ReportError(Status(StatusCode::kInvalidArgument, "--setup needs --instrument ballbar"));
  if (args.probe_radius_mm && args.instrument != "probe_artifacts")
    return ReportError(Status(StatusCode::kInvalidArgument, "--probe-radius-mm needs --instrument probe_artifacts"));
  if (args.instrument == "datum_ball") return RunDatumBall(args);
  if (args.instrument == "probe_artifacts") return RunProbeArtifacts(args);
  if (args.instrument == "ballbar") return RunBallbar(args);
  auto labelling = ParseAnchor(args.anchor);
  if (!labelling.ok()) return ReportError(labelling.status());
  pipeline::IdentifyRequest request = args.request;
  request.labelling = *labelling;
  request.gap_check = !args.no_gap_check;
  request.info = Info;
  auto report = pipeline::IdentifyPointFile(request);
  if (!report.ok()) return ReportError(report.status());
  return WriteJsonOrText(args.json, pipeline::IdentificationJson(*report),
                         [&] { return pipeline::IdentificationSummary(*report); });
}

}  // namespace

Command RegisterIdentify(CLI::App& app) {
  auto args = std::make_shared<IdentifyArgs>();
  const std::string names = testpieces::PieceNameList();
  CLI::App* sub = app.add_subcommand(
      "identify",
      "Identify machine errors from a measured test piece.\n"
      "Every labelled CMM point is put in the part frame through the datum frame of the piece's inspection\n"
      "plan and fitted by least squares through the full kinematic chain (the cut each point came from).\n"
      "Turning piece: the seed 002 Table 2 set and the X-Y squareness E_C(0X)Y (um, urad) with ISO 230-1\n"
      "symbols, the closed-form solution of the GD&T items beside it, and the C-axis radial/tilt error motions.\n"
      "3-axis pieces: squareness and the straightness profiles of the faces. Parameters the data cannot separate are reported as such,\n"
      "with the combinations that are determined. Uncertainty k = 1; 95 % intervals.");
  sub->add_option("POINTS", args->request.points_path,
                  "measured point file (tpcal points CSV, PLY, PCD, xyz text; mm), or with --instrument datum_ball "
                  "a ball-position file (tpcal ballpos v1), with --instrument probe_artifacts a probed-point file "
                  "(tpcal probepts v1), with --instrument ballbar a ball-bar file (tpcal ballbar v1)")
      ->required();
  sub->add_option("--instrument", args->instrument,
                  "datum_ball: POINTS holds datum-ball centres at rotary commands (touch probe, R-test); the location "
                  "errors of the rotary axes and the squareness of the linear axes (seed 001) are identified, the "
                  "ball centre fitted as a nuisance; --machine is the B/C or A/C table (default: the nominal one "
                  "the file's rotary columns name); a u_um column weights each reading (residual / u_um); u by "
                  "analytic, jackknife and Monte Carlo (200 re-identifications, seed 1). `tpcal simulate "
                  "--instrument datum_ball` writes such a file.\n"
                  "probe_artifacts: POINTS holds touches on artifacts fixed to an A/C table at indexed A x C "
                  "positions (seed 000); the table pose at every position (um, urad, relative to the reference "
                  "pose) with the linear axes' squareness (urad, written with the maps), then the error maps of the A axis (E_XA..E_CA over A) and of the C axis (E_XC..E_CC over "
                  "C at every A, zero mean over C) with u (k = 1) and 95 % intervals; what the plan cannot "
                  "determine is named. `tpcal simulate --instrument probe_artifacts` writes such a file.\n"
                  "ballbar: POINTS holds double-ball-bar length changes (um) of the installations of --setup "
                  "(seed 003; ISO 230-4): for each turned rotary axis its six error motions (E_X..E_C, um and "
                  "urad) at every measured angle with u (k = 1) and 95 % intervals, the bar-length offsets and "
                  "ball centring fitted and removed as set-up terms, and the families the installations cannot "
                  "separate named; for each circle installation the circular-test figures (circular deviation, "
                  "hysteresis, squareness, scale mismatch, reversal) with u; --machine default: the nominal "
                  "bhead_ctable (seed 003) when an installation turns a rotary axis, else xyz")
      ->check(CLI::IsMember({"datum_ball", "probe_artifacts", "ballbar"}));
  sub->add_option("--setup", args->setup,
                  "with --instrument ballbar (required): the installations (tpcal.ballbar_setup/1 YAML: kind, "
                  "turned axis or plane, ball positions in mm, nominal bar length in mm)");
  sub->add_option("--artifacts", args->artifacts,
                  "with --instrument probe_artifacts: the artifacts (tpcal.artifacts/1 YAML, part frame, mm); "
                  "default: seed 000's three 30 x 30 x 60 mm columns at (100, 0), (-100, 0), (0, 100)");
  sub->add_option("--reference-pose", args->reference_pose_deg,
                  "with --instrument probe_artifacts: A,C (deg) of the position whose table pose is zero by "
                  "definition (the artifacts are located there)")
      ->delimiter(',')
      ->capture_default_str();
  sub->add_option("--probe-radius-mm", args->probe_radius_mm,
                  "with --instrument probe_artifacts: the stylus ball radius the touches were taken with, mm (a "
                  "touch's linear command is its contact minus the radius along the approach; it places the "
                  "squareness's columns); default 3 (seed 000's 6 mm ruby)");
  sub->add_option("--html", args->html,
                  "with --instrument probe_artifacts: an offline page with each error map against its angle "
                  "(95 % bands)");
  sub->add_option("--errors-out", args->errors_out,
                  "with --instrument: also write the identified errors as tpcal.errors/1 (for simulate --errors and "
                  "diagnose --reference); errors the plan cannot identify are named in a comment, not written");
  sub->add_option("--ball", args->ball_mm,
                  "with --instrument: the ball centre X,Y,Z (mm, part frame) when it is known (e.g. calibrated on a "
                  "CMM); default: fitted as a nuisance with the errors")
      ->delimiter(',');
  sub->add_option("--testpiece", args->request.testpiece, "test piece: " + names)->capture_default_str();
  sub->add_option("--config", args->request.config_path, "test-piece configuration YAML (schema tpcal.testpiece/1)");
  sub->add_option("--machine", args->request.machine_path, "machine model YAML (default: nominal ac_table or xyz)");
  AddAnchorOption(sub, &args->anchor);
  AddColumnOption(sub, &args->request.columns);
  sub->add_option("--uncertainty", args->request.uncertainty,
                  "jackknife (delete one point, and one feature), analytic (Gauss-Newton), mc (GUM S1 Monte "
                  "Carlo) or all (primary: jackknife)")
      ->check(CLI::IsMember({"jackknife", "analytic", "mc", "all"}))
      ->capture_default_str();
  sub->add_option("--parameters", args->request.parameters, "parameters to identify (default: the piece's standard set)")
      ->delimiter(',');
  sub->add_option("--mc-trials", args->request.mc_trials, "Monte Carlo trials")->capture_default_str()->check(CLI::Range(10, 10000000));
  sub->add_option("--subset-trials", args->request.subset_trials,
                  "also seed 002 section 5's method for comparison: this many random 3-point subsets per feature "
                  "(0 = off; it overstates u for well-spread points)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000000));
  sub->add_option("--seed", args->request.seed, "Monte Carlo and random-subset seed")->capture_default_str();
  sub->add_flag("--keep-outliers", args->request.keep_outliers,
               "keep the probe hits and patches the outlier screen flags (still listed); default: left out");
  sub->add_flag("--no-gap-check", args->no_gap_check,
               "skip the diagnosis of the gap against the identified model (by default a verdict other than "
               "'none' is reported as a warning: the errors may be biased by an effect the model does not hold)");
  sub->add_option("--json", args->json, "write JSON (schema tpcal.identification/1) to this file; '-' for stdout");
  return {sub, [args] { return RunIdentify(*args); }};
}

}  // namespace tpcal::cli
