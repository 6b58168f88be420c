// tpcal diagnose POINTS --testpiece NAME [--config TP.yaml] [--machine M.yaml] [--reference ERRORS.yaml|REF_POINTS]
//                 [--anchor FEATURE@X,Y,Z] [--noise-um S] [--json OUT] [--html OUT]
// tpcal diagnose --validate [--testpiece NAME] [--config TP.yaml] [--trials N] [--seed S]
//                 [--magnitudes 1,2,5,10,20] [--noise 0.5,1,2] [--families F,...] [--markdown OUT]
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cctype>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "kinematics/errors_yaml.h"
#include "pipeline/io/atomic_file.h"
#include "pipeline/cli/anchor_option.h"
#include "pipeline/cli/commands.h"
#include "pipeline/diagnosis/diagnosis.h"
#include "pipeline/report/diagnosis_json.h"
#include "pipeline/diagnosis/diagnosis_validate.h"
#include "pipeline/piece_loader.h"
#include "pipeline/io/point_io.h"
#include "pipeline/raw_scan_labeling.h"
#include "testpieces/named_pieces.h"

namespace tpcal::cli {
namespace {

struct DiagnoseArgs {
  std::string points;
  std::string testpiece = "turning";
  std::string config;
  std::string machine;
  std::string anchor;  // FEATURE@X,Y,Z: the symmetric labelling of a raw scan
  std::string reference;
  double noise_um = 0.0;
  double alpha = 0.01;
  std::string json;
  std::string html;
  bool validate = false;
  int trials = 2;
  std::uint64_t seed = 1;
  std::vector<double> magnitudes = {1, 2, 5, 10, 20};
  std::vector<double> noise_levels = {0.5, 1.0, 2.0};
  std::vector<std::string> families;
  std::string markdown;
  bool raw_peak = false;
  bool no_placement = false;
  bool testpiece_given = false;  // --testpiece was on the command line (not the default)
};

using Setup = pipeline::LoadedPiece;

// NAME (testpieces/named_pieces.h) or a piece config file; with both, the file must be for the
// named piece (testpiece_given: --testpiece was on the command line, not the default).
Result<Setup> LoadSetup(const DiagnoseArgs& a, bool testpiece_given) {
  return pipeline::LoadPiece({.testpiece = a.testpiece, .config_path = a.config, .machine_path = a.machine,
                              .config_must_match_name = testpiece_given,
                              .wording = {.unknown_name_prefix = "--testpiece: ", .unknown_name_suffix = " (or --config FILE)"}});
}

int RunValidate(const DiagnoseArgs& args, const Setup& setup) {
  pipeline::ValidationOptions v;
  v.trials = args.trials;
  v.seed = args.seed;
  v.magnitudes = args.magnitudes;
  v.noise_um = args.noise_levels;
  v.families = args.families;
  v.scale_raw_peak = args.raw_peak;
  v.random_placement = !args.no_placement;
  Info(fmt::format("tpcal diagnose --validate: {} piece, seed {}, {} trial(s) per family, magnitude and noise level",
                   setup.piece.name, args.seed, args.trials));
  auto summary = pipeline::RunValidation(setup.piece, setup.machine, v);
  if (!summary.ok()) return ReportError(summary.status());
  const std::string md = fmt::format("Diagnosis validation: {} piece, seed {}, trials {}, magnitudes {} ({} peak), noise {} um\n\n",
                                     setup.piece.name, args.seed, args.trials, fmt::join(args.magnitudes, ","),
                                     args.raw_peak ? "raw signature" : "visible signature",
                                     fmt::join(args.noise_levels, ",")) +
                         pipeline::ValidationMarkdown(*summary);
  std::cout << md;
  if (!args.markdown.empty()) {
    if (Status s = pipeline::WriteFileAtomic(args.markdown, md); !s.ok()) return ReportError(s);
    Info("wrote " + args.markdown);
  }
  return kExitOk;
}

int RunDiagnose(const DiagnoseArgs& args) {
  auto labelling = ParseAnchor(args.anchor);
  if (!labelling.ok()) return ReportError(labelling.status());
  auto setup = LoadSetup(args, args.testpiece_given);
  if (!setup.ok()) return ReportError(setup.status());
  if (args.validate) return RunValidate(args, *setup);
  if (args.points.empty()) return ReportError(Status(StatusCode::kInvalidArgument, "diagnose: POINTS is required (or --validate)"));
  auto points = pipeline::ReadPoints(args.points);
  if (!points.ok()) return ReportError(points.status());
  auto labelled = pipeline::LabelIfRawScan(setup->piece, &*points, *labelling);  // a raw scan: label it first
  if (!labelled.ok()) return ReportError(labelled.status());
  if (labelled->has_value()) Info("raw scan labelled: " + (*labelled)->BriefReport());
  pipeline::DiagnosisOptions options;
  options.noise_um = args.noise_um;
  options.alpha = args.alpha;
  // --reference: machine errors (.yaml/.yml) or a point file (an extension ReadPoints knows).
  std::optional<PointSet> reference_points;
  if (!args.reference.empty()) {
    std::string ext = std::filesystem::path(args.reference).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    options.reference_name = std::filesystem::path(args.reference).filename().string();
    if (ext == ".yaml" || ext == ".yml") {
      auto ref = kinematics::LoadErrorState(args.reference, setup->machine);
      if (!ref.ok()) return ReportError(ref.status());
      options.reference = std::move(*ref);
      options.reference_path = args.reference;
    } else if (pipeline::PointFormatFromExtension(args.reference) != pipeline::PointFormat::kAuto) {
      auto ref = pipeline::ReadPoints(args.reference);
      if (!ref.ok()) return ReportError(ref.status());
      reference_points = std::move(*ref);
    } else {
      return ReportError(Status(StatusCode::kInvalidArgument,
                                "--reference " + args.reference +
                                    ": expected machine errors (.yaml, .yml) or a point file (.csv, .ply, .pcd, .xyz, .txt)"));
    }
  }
  Info(fmt::format("tpcal diagnose: {} points of the {} from {}", points->size(), setup->piece.name, args.points));
  auto result = reference_points
                    ? pipeline::DiagnoseAgainstPoints(setup->piece, setup->machine, *points, *reference_points, options)
                    : pipeline::Diagnose(setup->piece, setup->machine, *points, options);
  if (!result.ok()) return ReportError(result.status());
  const std::map<std::string, std::string> inputs = {
      {"points", args.points},
      {"testpiece", args.config.empty() ? args.testpiece : args.config},
      {"machine", args.machine.empty() ? "nominal" : args.machine},
      {"reference", args.reference},
      {"reference_kind", args.reference.empty() ? "" : (reference_points ? "points" : "machine errors")},
      {"noise_um", fmt::format("{}", args.noise_um)},
      {"alpha", fmt::format("{}", args.alpha)}};
  const std::string json = pipeline::DiagnosisJson(*result, inputs);
  if (args.json == "-") {
    std::cout << json;
  } else {
    std::cout << pipeline::DiagnosisText(*result);
    if (!args.json.empty()) {
      if (Status s = pipeline::WriteFileAtomic(args.json, json); !s.ok()) return ReportError(s);
      Info("wrote " + args.json);
    }
  }
  if (!args.html.empty()) {
    if (Status s = pipeline::WriteFileAtomic(args.html, pipeline::DiagnosisHtml(*result, "tpcal diagnosis: " + args.points));
        !s.ok())
      return ReportError(s);
    Info("wrote " + args.html);
  }
  return kExitOk;
}

}  // namespace

Command RegisterDiagnose(CLI::App& app) {
  auto args = std::make_shared<DiagnoseArgs>();
  CLI::App* sub = app.add_subcommand(
      "diagnose",
      "Diagnose the sim-to-real gap of a measured test piece.\n"
      "The base model (location errors and squareness, or --reference machine errors) is fitted to the points;\n"
      "the gap (measured minus model) is summarised per feature, operation, A index, machining time and C harmonic;\n"
      "a catalogue of unmodelled effects (thermal drift, straightness, positioning, rotary error motion and\n"
      "positioning, tool deflection, servo reversal, probe radius) is ranked by cross-validated gap reduction\n"
      "(leave one feature out: each feature predicted by the fit on the others; features whose points alone fix a\n"
      "direction of the model are not held out and are listed) and a nested F-test; `none` when nothing beats\n"
      "noise, with the families the data cannot tell apart.\n"
      "--reference REF.csv (a point file, e.g. the piece simulated from known errors): the gap is measured minus\n"
      "reference point by point, each file in its own datum frame, points matched within their feature by order\n"
      "when the counts match and every pair's nominal positions lie within 1 mm, otherwise by nearest nominal\n"
      "position (within 1 mm, else the point is skipped); only the re-alignment is fitted.\n"
      "--validate runs the check on simulated pieces with withheld effects and prints the confusion matrix.");
  sub->add_option("POINTS", args->points, "measured point file (tpcal points CSV, PLY, PCD, xyz text; mm)");
  CLI::Option* testpiece =
      sub->add_option("--testpiece", args->testpiece,
                      "test piece: " + testpieces::PieceNameList() + " (iso10791_m1 = iso10791_m1_320)")
          ->capture_default_str();
  sub->add_option("--config", args->config,
                  "test-piece configuration YAML (tpcal.testpiece/1) instead of NAME's (with --testpiece: the same piece)");
  sub->add_option("--machine", args->machine, "machine model YAML (default: nominal ac_table or xyz)");
  AddAnchorOption(sub, &args->anchor);
  sub->add_option("--reference", args->reference,
                  "the sim instead of the fitted base: machine errors YAML (tpcal.errors/1, .yaml/.yml), not refitted, "
                  "or a point file (.csv, .ply, .pcd, .xyz, .txt) of the same piece, compared point by point");
  sub->add_option("--noise-um", args->noise_um, "known CMM noise sigma (um) for 'beyond noise'; 0 = estimated")
      ->capture_default_str();
  sub->add_option("--alpha", args->alpha, "family-wise false-alarm probability of the verdict")->capture_default_str();
  sub->add_option("--json", args->json, "write the tpcal.diagnosis/1 JSON here ('-' for stdout)");
  sub->add_option("--html", args->html, "write a readable HTML report here");
  sub->add_flag("--validate", args->validate, "run the validation on simulated pieces with withheld effects");
  sub->add_option("--trials", args->trials, "validation: trials per family, magnitude and noise level")->capture_default_str();
  sub->add_option("--seed", args->seed, "validation: random seed")->capture_default_str();
  sub->add_option("--magnitudes", args->magnitudes, "validation: peak visible signature / noise sigma")->delimiter(',');
  sub->add_option("--noise", args->noise_levels, "validation: CMM noise sigmas (um)")->delimiter(',');
  sub->add_option("--families", args->families, "validation: families to withhold (default all and none)")->delimiter(',');
  sub->add_option("--markdown", args->markdown, "validation: also write the Markdown table here");
  sub->add_flag("--no-placement", args->no_placement, "validation: the CMM frame is the datum frame (no random placement)");
  sub->add_flag("--raw-peak", args->raw_peak,
                "validation: magnitudes scale the raw signature's peak (default: the part the base model cannot absorb)");
  return {sub, [args, testpiece] {
            args->testpiece_given = testpiece->count() > 0;
            return RunDiagnose(*args);
          }};
}

}  // namespace tpcal::cli
