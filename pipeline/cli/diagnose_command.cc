// tpcal diagnose POINTS --testpiece NAME [--config TP.yaml] [--machine M.yaml] [--reference ERRORS.yaml|REF_POINTS]
//                 [--reference INSTRUMENT_FILE --reference-instrument NAME [--reference-setup S.yaml]
//                  [--reference-probe-radius-mm R]]
//                 [--anchor FEATURE@X,Y,Z] [--noise-um S] [--json OUT] [--html OUT]
// tpcal diagnose --validate [--testpiece NAME] [--config TP.yaml] [--trials N] [--seed S]
//                 [--magnitudes 1,2,5,10,20] [--noise 0.5,1,2] [--families F,...] [--markdown OUT]
//                 [--reference-instrument datum_ball|probe_artifacts|ballbar [--reference-noise-um U]]
#include <CLI/CLI.hpp>

#include <memory>
#include <string>

#include "pipeline/cli/anchor_option.h"
#include "pipeline/cli/column_option.h"
#include "pipeline/cli/commands.h"
#include "pipeline/cli/diagnose_validate.h"
#include "pipeline/diagnose_stage.h"
#include "pipeline/io/atomic_file.h"
#include "pipeline/report/diagnosis_json.h"
#include "testpieces/named_pieces.h"

namespace tpcal::cli {
namespace {

struct DiagnoseArgs {
  pipeline::DiagnoseRequest request;
  std::string anchor;  // FEATURE@X,Y,Z: the symmetric labelling of a raw scan
  std::string json;
  std::string html;
  ValidateArgs validate;
};

// The JSON or the text (and the JSON file), then the HTML report.
int WriteDiagnosis(const DiagnoseArgs& args, const pipeline::DiagnoseStageResult& stage) {
  const int exit = WriteJsonOrText(args.json, pipeline::DiagnosisJson(stage.diagnosis, stage.inputs),
                                   [&] { return pipeline::DiagnosisText(stage.diagnosis); });
  if (exit != kExitOk || args.html.empty()) return exit;
  const std::string html = pipeline::DiagnosisHtml(stage.diagnosis, "tpcal diagnosis: " + args.request.points_path);
  if (Status s = pipeline::WriteFileAtomic(args.html, html); !s.ok()) return ReportError(s);
  Info("wrote " + args.html);
  return kExitOk;
}

int RunDiagnose(const DiagnoseArgs& args) {
  auto labelling = ParseAnchor(args.anchor);
  if (!labelling.ok()) return ReportError(labelling.status());
  pipeline::DiagnoseRequest request = args.request;
  request.labelling = *labelling;
  request.info = Info;
  auto setup = pipeline::LoadDiagnosisPiece(request);
  if (!setup.ok()) return ReportError(setup.status());
  if (args.validate.on) return RunValidate(args.validate, *setup);
  if (request.points_path.empty())
    return ReportError(Status(StatusCode::kInvalidArgument, "diagnose: POINTS is required (or --validate)"));
  auto stage = pipeline::RunDiagnoseStage(*setup, request);
  if (!stage.ok()) return ReportError(stage.status());
  return WriteDiagnosis(args, *stage);
}

// POINTS, the piece, the reference and the outputs; returns --testpiece (given or not).
CLI::Option* AddDiagnoseOptions(CLI::App* sub, DiagnoseArgs* args) {
  pipeline::DiagnoseRequest* r = &args->request;
  sub->add_option("POINTS", r->points_path, "measured point file (tpcal points CSV, PLY, PCD, xyz text; mm)");
  CLI::Option* testpiece =
      sub->add_option("--testpiece", r->testpiece,
                      "test piece: " + testpieces::PieceNameList() + " (iso10791_m1 = iso10791_m1_320)")
          ->capture_default_str();
  sub->add_option("--config", r->config_path,
                  "test-piece configuration YAML (tpcal.testpiece/1) instead of NAME's (with --testpiece: the same piece)");
  sub->add_option("--machine", r->machine_path, "machine model YAML (default: nominal ac_table or xyz)");
  AddAnchorOption(sub, &args->anchor);
  AddColumnOption(sub, &r->columns);
  sub->add_option("--reference", r->reference_path,
                  "the sim instead of the fitted base: machine errors YAML (tpcal.errors/1, .yaml/.yml), not refitted, "
                  "or a point file (.csv, .ply, .pcd, .xyz, .txt) of the same piece, compared point by point, "
                  "or an instrument's file (with --reference-instrument)");
  sub->add_option("--reference-instrument", r->reference_instrument,
                  "--reference is this instrument's file, identified first: datum_ball (tpcal ballpos v1: the piece "
                  "is compared with it parameter by parameter), probe_artifacts (tpcal probepts v1) or ballbar "
                  "(tpcal ballbar v1; needs --reference-setup): error maps of the rotary axes (probe_artifacts: "
                  "compared with the piece through their parameter equivalent and its squareness; ballbar: "
                  "through the piece simulated from them only, its own parameters fitted from the piece); the gap "
                  "is diagnosed against the instrument");
  sub->add_option("--reference-setup", r->reference_setup,
                  "with --reference-instrument probe_artifacts: its artifacts (tpcal.artifacts/1; default seed 000's "
                  "three columns); ballbar: its installations (tpcal.ballbar_setup/1, required)");
  sub->add_option("--reference-probe-radius-mm", r->reference_probe_radius_mm,
                  "with --reference-instrument probe_artifacts: the stylus ball radius its touches were taken "
                  "with, mm (default 3)");
  sub->add_option("--noise-um", r->noise_um, "known CMM noise sigma (um) for 'beyond noise'; 0 = estimated")
      ->capture_default_str();
  sub->add_option("--alpha", r->alpha, "family-wise false-alarm probability of the verdict")->capture_default_str();
  sub->add_flag("--keep-outliers", r->keep_outliers,
               "keep the probe hits and patches the outlier screen flags (still listed); default: left out");
  sub->add_option("--json", args->json, "write the tpcal.diagnosis/1 JSON here ('-' for stdout)");
  sub->add_option("--html", args->html, "write a readable HTML report here");
  return testpiece;
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
      "--reference BALLPOS.csv --reference-instrument datum_ball: the datum-ball test is identified, the piece is\n"
      "identified with the same parameters, the two are compared (value +- u each, z; Bonferroni at --alpha), and\n"
      "the gap is diagnosed against the instrument's errors updated by the piece within the instrument's covariance\n"
      "(u alone for a .json reference).\n"
      "--reference PROBEPTS.csv --reference-instrument probe_artifacts [--reference-setup ARTIFACTS.yaml], or\n"
      "--reference BALLBAR.csv --reference-instrument ballbar --reference-setup SETUP.yaml: the rotary axes' error\n"
      "maps are identified and the gap is diagnosed against them, the directions their own uncertainty moves the\n"
      "piece along fitted (probe_artifacts: compared parameter by parameter through the maps' parameter equivalent\n"
      "and the squareness it fits; ballbar: no parameter, the table says why).\n"
      "A file of more than 3000 points (no point --reference) is identified, re-aligned and re-associated as tpcal\n"
      "run does (more than 250 000: also pooled into scan-line cells, whose noise the tests weigh).\n"
      "--validate runs the check on simulated pieces with withheld effects and prints the confusion matrix.");
  CLI::Option* testpiece = AddDiagnoseOptions(sub, args.get());
  AddValidateOptions(sub, &args->validate);
  return {sub, [args, testpiece] {
            args->request.testpiece_given = testpiece->count() > 0;
            return RunDiagnose(*args);
          }};
}

}  // namespace tpcal::cli
