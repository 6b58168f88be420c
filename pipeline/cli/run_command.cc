// tpcal run PIPELINE.yaml [--out DIR] ...
// tpcal run --testpiece turning --points cmm.csv --out DIR [--machine M.yaml] [--seed N] [--anchor FEATURE@X,Y,Z]
// tpcal run [PIPELINE.yaml] --batch DIR_OR_GLOB --out DIR [-j N]
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <unistd.h>

#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/batch.h"
#include "pipeline/cli/anchor_option.h"
#include "pipeline/cli/commands.h"
#include "pipeline/run_config.h"
#include "pipeline/run_output.h"
#include "pipeline/run_stage.h"
#include "pipeline/report/svg_figures.h"
#include "testpieces/named_pieces.h"

namespace tpcal::cli {
namespace {

struct RunArgs {
  std::string pipeline;
  std::string testpiece;
  std::string points;
  std::string out;
  std::string machine;
  std::string truth;
  std::string anchor;  // FEATURE@X,Y,Z: overrides raw_scan.anchor_feature / anchor_near_mm
  std::vector<std::string> parameters;
  std::optional<std::uint64_t> seed;
  std::optional<int> mc_trials;
  std::string batch;
  int threads = 0;
  bool quiet = false;
  CLI::App* root = nullptr;
};

// Progress lines only on a terminal, never with -q (global or on the subcommand).
bool ShowProgress(const RunArgs& a) {
  const bool global_quiet = a.root && a.root->get_option_no_throw("--quiet") &&
                            a.root->get_option_no_throw("--quiet")->count() > 0;
  return !a.quiet && !global_quiet && ::isatty(STDERR_FILENO) == 1;
}

Result<pipeline::PipelineConfig> BuildConfig(const RunArgs& a, bool batch) {
  pipeline::PipelineConfig c;
  if (!a.pipeline.empty()) {
    auto loaded = pipeline::LoadPipelineConfig(a.pipeline);
    if (!loaded.ok()) return loaded.status();
    c = *loaded;
  }
  if (!a.testpiece.empty()) c.testpiece = a.testpiece;
  if (!a.points.empty()) c.points = a.points;
  if (!a.machine.empty()) c.machine = a.machine;
  if (!a.truth.empty()) c.truth = a.truth;
  if (!a.parameters.empty()) c.parameters = a.parameters;
  if (a.seed) c.seed = *a.seed;
  if (a.mc_trials) c.monte_carlo_trials = *a.mc_trials;
  if (!a.out.empty()) c.out = a.out;
  if (!a.anchor.empty()) {
    auto anchor = ParseAnchor(a.anchor);
    if (!anchor.ok()) return anchor.status();
    c.anchor_feature = anchor->anchor_feature;
    c.anchor_near_mm = anchor->anchor_near_mm;
  }
  if (batch && c.points.empty()) c.points = "(batch)";
  if (Status s = c.Validate(); !s.ok()) return s;
  if (c.out.empty()) return Status(StatusCode::kInvalidArgument, "no output directory: give --out DIR (or 'out' in the pipeline file)");
  return c;
}

void PrintParameters(const pipeline::RunResult& r) {
  std::cout << fmt::format("{:<16} {:<22} {:>10} {:>9} {:>23}  {}\n", "parameter", "ISO 230-1", "value", "u (k=1)",
                           "95 % interval", "unit");
  for (const auto& p : r.stage.identification.parameters) {
    // um and urad with fixed decimals; polynomial coefficients (um per mm^k) with 4 significant digits.
    const bool fixed = p.unit == "um" || p.unit == "urad";
    if (p.identifiable && fixed)
      std::cout << fmt::format("{:<16} {:<22} {:>10.2f} {:>9.3f} [{:>9.2f}, {:>9.2f}]  {}\n", p.name, pipeline::ShortIsoSymbol(p.iso_symbol),
                               p.value, p.u, p.ci95_low, p.ci95_high, p.unit);
    else if (p.identifiable)
      std::cout << fmt::format("{:<16} {:<22} {:>10.4g} {:>9.3g} [{:>9.4g}, {:>9.4g}]  {}\n", p.name, pipeline::ShortIsoSymbol(p.iso_symbol),
                               p.value, p.u, p.ci95_low, p.ci95_high, p.unit);
    else
      std::cout << fmt::format("{:<16} {:<22} {:>10} {:>9} {:>23}  {}\n", p.name, pipeline::ShortIsoSymbol(p.iso_symbol), "n/a", "-",
                               "not identifiable", p.unit);
  }
  const auto& ia = r.stage.identification.identifiability;
  std::cout << fmt::format("rank {} of {}, condition number {:.3g}; residual RMS {:.3f} um -> {:.3f} um\n", ia.rank,
                           ia.num_parameters, ia.condition_number, r.stage.identification.rms_before_um,
                           r.stage.identification.rms_after_um);
  if (r.diagnosis)
    std::cout << fmt::format("gap diagnosis: {} ({}), shrink {:.1f} % (cross-validated {:.1f} %)\n",
                             r.diagnosis->verdict.family, r.diagnosis->verdict.name, r.diagnosis->verdict.shrink_pct,
                             r.diagnosis->verdict.cv_shrink_pct);
  else if (r.config.diagnose)
    std::cout << "gap diagnosis: not made: " << r.diagnosis_status.ToString() << "\n";
}

int RunSingle(const RunArgs& a) {
  auto config = BuildConfig(a, false);
  if (!config.ok()) return ReportError(config.status());
  const bool progress = ShowProgress(a);
  pipeline::RunOptions options;
  options.read_threads = a.threads;
  if (progress) {
    options.progress = [](std::string_view stage) {
      if (stage == "done")
        std::cerr << "\r\033[K";
      else
        std::cerr << "\r\033[Ktpcal run: " << stage << "..." << std::flush;
    };
  }
  auto result = pipeline::RunPipeline(*config, options);
  if (!result.ok()) {
    if (progress) std::cerr << "\r\033[K";
    return ReportError(result.status());
  }
  if (progress) std::cerr << "\r\033[Ktpcal run: writing " << config->out << std::flush;
  const Status written = pipeline::WriteDirectoryAtomic(config->out, pipeline::RenderRunFiles(*result));
  if (progress) std::cerr << "\r\033[K";
  if (!written.ok()) return ReportError(written);
  PrintParameters(*result);
  std::string times;
  for (const auto& t : result->timings) times += fmt::format(" {} {:.3f}s", t.stage, t.seconds);
  if (progress) Info("stages:" + times);
  if (!a.quiet) Info("wrote " + config->out + "/report.html, result.json, CSV tables and figures/");
  return kExitOk;
}

int RunBatchCommand(const RunArgs& a) {
  auto config = BuildConfig(a, true);
  if (!config.ok()) return ReportError(config.status());
  auto files = pipeline::ExpandBatchInputs(a.batch);
  if (!files.ok()) return ReportError(files.status());
  pipeline::BatchOptions options;
  options.base = *config;
  options.out_dir = config->out;
  options.threads = a.threads;
  const bool progress = ShowProgress(a);
  auto on_item = [progress](const pipeline::BatchItem& item, std::size_t done, std::size_t total) {
    if (!item.status.ok()) {
      if (progress) std::cerr << "\r\033[K";
      std::cerr << "FAILED " << item.status.ToString() << "\n";
    }
    if (progress) std::cerr << fmt::format("\r\033[Ktpcal run --batch: {}/{} {}", done, total, item.points) << std::flush;
  };
  auto result = pipeline::RunBatch(*files, options, on_item);
  if (progress) std::cerr << "\r\033[K";
  if (!result.ok()) return ReportError(result.status());
  const std::size_t n = result->items.size();
  const std::string line = fmt::format("tpcal run --batch: {} files, {} ok, {} failed; summary {}/summary.csv", n,
                                       n - static_cast<std::size_t>(result->failed), result->failed, config->out);
  if (result->failed > 0)
    std::cerr << line << "\n";
  else if (!a.quiet)
    Info(line);
  return result->failed > 0 ? kExitSomeFailed : kExitOk;
}

}  // namespace

Command RegisterRun(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  args->root = &app;
  CLI::App* sub = app.add_subcommand(
      "run",
      "The whole pipeline: read points, fit and evaluate GD&T, identify the machine errors with uncertainty and\n"
      "identifiability, and write DIR/report.html (self-contained), result.json (schema tpcal.run/1), CSV tables\n"
      "and SVG figures, atomically. With --batch, every point file of a directory or glob, in parallel, with\n"
      "DIR/summary.csv trending each machine error across the runs (exit 1 if any file failed).");
  sub->add_option("PIPELINE", args->pipeline, "pipeline YAML (schema tpcal.pipeline/1, pipeline/run_config.h)");
  sub->add_option("--testpiece", args->testpiece,
                  "test piece: " + testpieces::PieceNameList() + ", or a tpcal.testpiece/1 YAML (default turning)");
  sub->add_option("--points", args->points, "measured point file (tpcal points CSV, PLY, PCD, xyz)");
  sub->add_option("--out", args->out, "output directory (replaced atomically; created if missing)");
  sub->add_option("--machine", args->machine, "machine YAML (tpcal.machine/1); default: the piece's nominal machine");
  sub->add_option("--truth", args->truth, "stated truth of a simulated sample (tpcal.sample_truth/1) to mark in the report");
  AddAnchorOption(sub, &args->anchor);
  sub->add_option("--parameters", args->parameters, "coefficients to identify (default: the piece's standard set)")
      ->delimiter(',');
  sub->add_option("--seed", args->seed, "Monte Carlo seed (default 1), written to every output");
  sub->add_option("--mc-trials", args->mc_trials, "GUM S1 Monte Carlo trials (default 2000; 0 = off)");
  sub->add_option("--batch", args->batch, "directory or glob of point files: run each, in parallel");
  sub->add_option("-j,--threads", args->threads, "worker threads (0 = all cores)")->capture_default_str();
  sub->add_flag("-q,--quiet", args->quiet, "no progress lines");
  return {sub, [args] { return args->batch.empty() ? RunSingle(*args) : RunBatchCommand(*args); }};
}

}  // namespace tpcal::cli
