// tpcal identify POINTS --testpiece NAME [--config TP.yaml] [--machine M.yaml] [--anchor FEATURE@X,Y,Z]
//                [--uncertainty jackknife|analytic|mc|all] [--parameters P,...] [--json OUT]
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "pipeline/cli/anchor_option.h"
#include "pipeline/cli/commands.h"
#include "pipeline/identify_report.h"
#include "pipeline/io/atomic_file.h"
#include "pipeline/piece_loader.h"
#include "pipeline/raw_scan_labeling.h"
#include "pipeline/report/identify_json.h"
#include "pipeline/report/identify_summary.h"
#include "testpieces/named_pieces.h"

namespace tpcal::cli {
namespace {

struct IdentifyArgs {
  std::string points;
  std::string testpiece = "turning";
  std::string config;
  std::string machine;
  std::string anchor;  // FEATURE@X,Y,Z: the symmetric labelling of a raw scan
  std::string uncertainty = "all";
  std::vector<std::string> parameters;
  int mc_trials = 2000;
  int subset_trials = 0;
  std::uint64_t seed = 1;
  std::string json;
};

int RunIdentify(const IdentifyArgs& args) {
  auto labelling = ParseAnchor(args.anchor);
  if (!labelling.ok()) return ReportError(labelling.status());
  auto setup = pipeline::LoadPiece({.testpiece = args.testpiece, .config_path = args.config, .machine_path = args.machine,
                                    .wording = {.name_piece_errors = true}});
  if (!setup.ok()) return ReportError(setup.status());
  auto points = pipeline::ReadLabelledPoints(args.points, setup->piece, *labelling);
  if (!points.ok()) return ReportError(points.status());
  if (points->raw_scan) Info("raw scan labelled: " + points->raw_scan->BriefReport());

  pipeline::IdentifyStageOptions options;
  options.parameters = args.parameters;
  options.identify = pipeline::IdentifyOptionsFor(args.uncertainty, args.mc_trials, args.subset_trials, args.seed);
  Info(fmt::format("tpcal identify: {} points of the {} from {}", points->points.size(), setup->piece.name, args.points));
  auto report = pipeline::BuildIdentificationReport(setup->piece, setup->machine, points->points, options);
  if (!report.ok()) return ReportError(report.status());
  const std::string json = pipeline::IdentificationJson(*report);
  if (args.json == "-") {
    std::cout << json;
    return kExitOk;
  }
  std::cout << pipeline::IdentificationSummary(*report);
  if (!args.json.empty()) {
    if (Status s = pipeline::WriteFileAtomic(args.json, json); !s.ok()) return ReportError(s);
    Info("wrote " + args.json);
  }
  return kExitOk;
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
  sub->add_option("POINTS", args->points, "measured point file (tpcal points CSV, PLY, PCD, xyz text; mm)")->required();
  sub->add_option("--testpiece", args->testpiece, "test piece: " + names)->capture_default_str();
  sub->add_option("--config", args->config, "test-piece configuration YAML (schema tpcal.testpiece/1)");
  sub->add_option("--machine", args->machine, "machine model YAML (default: nominal ac_table or xyz)");
  AddAnchorOption(sub, &args->anchor);
  sub->add_option("--uncertainty", args->uncertainty,
                  "jackknife (delete one point, and one feature), analytic (Gauss-Newton), mc (GUM S1 Monte "
                  "Carlo) or all (primary: jackknife)")
      ->check(CLI::IsMember({"jackknife", "analytic", "mc", "all"}))
      ->capture_default_str();
  sub->add_option("--parameters", args->parameters, "parameters to identify (default: the piece's standard set)")
      ->delimiter(',');
  sub->add_option("--mc-trials", args->mc_trials, "Monte Carlo trials")->capture_default_str()->check(CLI::Range(10, 10000000));
  sub->add_option("--subset-trials", args->subset_trials,
                  "also seed 002 section 5's method for comparison: this many random 3-point subsets per feature "
                  "(0 = off; it overstates u for well-spread points)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000000));
  sub->add_option("--seed", args->seed, "Monte Carlo and random-subset seed")->capture_default_str();
  sub->add_option("--json", args->json, "write JSON (schema tpcal.identification/1) to this file; '-' for stdout");
  return {sub, [args] { return RunIdentify(*args); }};
}

}  // namespace tpcal::cli
