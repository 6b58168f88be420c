// tpcal identify POINTS --testpiece NAME [--config TP.yaml] [--machine M.yaml] [--anchor FEATURE@X,Y,Z]
//                [--uncertainty jackknife|analytic|mc|all] [--parameters P,...] [--json OUT]
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "pipeline/io/atomic_file.h"
#include "pipeline/cli/anchor_option.h"
#include "pipeline/cli/commands.h"
#include "pipeline/identify_json.h"
#include "pipeline/piece_loader.h"
#include "pipeline/io/point_io.h"
#include "pipeline/raw_scan_labeling.h"
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

std::string Fixed(double v, int digits = 2) { return fmt::format("{:.{}f}", v, digits); }

void PrintSummary(const pipeline::IdentificationReport& r) {
  const auto& id = r.stage.identification;
  std::cout << fmt::format("{} on {}: {} points in {} features; residual RMS {} um before, {} um after (sigma {} um)\n\n",
                           r.testpiece, r.machine, id.num_observations, id.num_groups, Fixed(id.rms_before_um, 3),
                           Fixed(id.rms_after_um, 3), Fixed(id.sigma_um, 3));
  std::cout << fmt::format("{:<15} {:>9} {:<5} {:>8} {:>8} {:>8} {:>19}  {}\n", "parameter", "value", "unit",
                           "u_anal", "u_jk_pt", "u_jk_ft", "95 % interval", "ISO 230-1");
  for (const auto& p : id.parameters) {
    if (!p.identifiable) {
      std::cout << fmt::format("{:<15} {:>9} {:<5}   not identifiable from this piece (see combinations)  {}\n",
                               p.name, "-", p.unit, p.iso_symbol);
      continue;
    }
    auto u_of = [&](kinematics::UncertaintyMethod m) {
      for (const auto& u : p.uncertainties)
        if (u.method == m && u.available) return Fixed(u.u);
      return std::string("-");
    };
    const std::string subset = u_of(kinematics::UncertaintyMethod::kRandomSubsets);
    std::cout << fmt::format("{:<15} {:>9} {:<5} {:>8} {:>8} {:>8} {:>19}  {}{}\n", p.name, Fixed(p.value), p.unit,
                             u_of(kinematics::UncertaintyMethod::kAnalytic),
                             u_of(kinematics::UncertaintyMethod::kJackknifePoints),
                             u_of(kinematics::UncertaintyMethod::kJackknifeGroups),
                             "[" + Fixed(p.ci95_low) + ", " + Fixed(p.ci95_high) + "]", p.iso_symbol,
                             subset == "-" ? std::string() : "  (random subsets: u " + subset + ")");
  }
  const auto& ident = id.identifiability;
  std::cout << fmt::format("\nidentifiability: rank {} of {}, condition number {:.3g}\n", ident.rank,
                           ident.num_parameters, ident.condition_number);
  for (const auto& c : ident.estimable)
    std::cout << fmt::format("  only the combination {} = {} +- {} is determined\n", c.text, Fixed(c.value), Fixed(c.u));
  for (const auto& m : r.error_motion)
    std::cout << fmt::format("C error motion {} ({}): radial P-V {} um, tilt P-V {} urad\n", m.name, m.faces,
                             Fixed(m.profile.radial_pv_um), Fixed(m.profile.tilt_pv_urad));
  for (const auto& s : r.straightness)
    std::cout << fmt::format("straightness {} from {}: {} um (LS P-V), {} um (minimum zone)\n", s.name, s.feature,
                             Fixed(s.pv_ls_um), Fixed(s.mz_um));
}

int RunIdentify(const IdentifyArgs& args) {
  auto labelling = ParseAnchor(args.anchor);
  if (!labelling.ok()) return ReportError(labelling.status());
  auto setup = pipeline::LoadPiece({.testpiece = args.testpiece, .config_path = args.config, .machine_path = args.machine,
                                    .wording = {.name_piece_errors = true}});
  if (!setup.ok()) return ReportError(setup.status());
  auto points = pipeline::ReadPoints(args.points);
  if (!points.ok()) return ReportError(points.status());
  auto labelled = pipeline::LabelIfRawScan(setup->piece, &*points, *labelling);  // a raw scan: label it first
  if (!labelled.ok()) return ReportError(labelled.status());
  if (labelled->has_value()) Info("raw scan labelled: " + (*labelled)->BriefReport());

  pipeline::IdentifyStageOptions options;
  options.parameters = args.parameters;
  auto& o = options.identify;
  o.seed = args.seed;
  if (args.uncertainty == "analytic") {
    o.primary = kinematics::UncertaintyMethod::kAnalytic;
    o.jackknife_groups = false;
  } else if (args.uncertainty == "mc") {
    o.primary = kinematics::UncertaintyMethod::kMonteCarlo;
    o.monte_carlo_trials = args.mc_trials;
    o.jackknife_groups = false;
  } else if (args.uncertainty == "jackknife") {
    o.primary = kinematics::UncertaintyMethod::kJackknifePoints;
  } else {  // all
    o.primary = kinematics::UncertaintyMethod::kJackknifePoints;
    o.monte_carlo_trials = args.mc_trials;
  }
  o.random_subset_trials = args.subset_trials;
  Info(fmt::format("tpcal identify: {} points of the {} from {}", points->size(), setup->piece.name, args.points));
  auto report = pipeline::BuildIdentificationReport(setup->piece, setup->machine, *points, options);
  if (!report.ok()) return ReportError(report.status());
  const std::string json = pipeline::IdentificationJson(*report);
  if (args.json == "-") {
    std::cout << json;
    return kExitOk;
  }
  PrintSummary(*report);
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
