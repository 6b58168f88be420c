// tpcal run PIPELINE.yaml [--out DIR] ...
// tpcal run --testpiece turning --points cmm.csv --out DIR [--machine M.yaml] [--seed N] [--anchor FEATURE@X,Y,Z]
// tpcal run [PIPELINE.yaml] --batch DIR_OR_GLOB --out DIR [-j N]
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <iostream>
#include <memory>
#include <string>

#include "pipeline/cli/anchor_option.h"
#include "pipeline/cli/column_option.h"
#include "pipeline/cli/commands.h"
#include "pipeline/cli/progress_line.h"
#include "pipeline/cli/run_args.h"
#include "pipeline/report/run_summary.h"
#include "pipeline/run_output.h"
#include "pipeline/run_stage.h"
#include "testpieces/named_pieces.h"

namespace tpcal::cli {

Result<pipeline::PipelineConfig> BuildRunConfig(const RunArgs& a, bool batch) {
  auto config = a.pipeline.empty() ? Result<pipeline::PipelineConfig>(pipeline::PipelineConfig{})
                                   : pipeline::LoadPipelineConfig(a.pipeline);
  if (!config.ok()) return config.status();
  auto anchor = ParseAnchor(a.anchor);
  if (!anchor.ok()) return anchor.status();
  pipeline::PipelineOverrides overrides = a.overrides;
  overrides.anchor_feature = anchor->anchor_feature;
  overrides.anchor_near_mm = anchor->anchor_near_mm;
  return pipeline::ApplyPipelineOverrides(*config, overrides, batch);
}

namespace {

int RunSingle(const RunArgs& a) {
  auto config = BuildRunConfig(a, false);
  if (!config.ok()) return ReportError(config.status());
  const ProgressLine progress(WantProgress(a.root, a.quiet));
  pipeline::RunOptions options;
  options.read_threads = a.threads;
  if (progress.on()) {
    options.progress = [&progress](std::string_view stage) {
      if (stage == "done")
        progress.Clear();
      else
        progress.Show("tpcal run: " + std::string(stage) + "...");
    };
  }
  auto result = pipeline::RunPipeline(*config, options);
  if (!result.ok()) {
    progress.Clear();
    return ReportError(result.status());
  }
  progress.Show("tpcal run: writing " + config->out);
  const Status written = pipeline::WriteDirectoryAtomic(config->out, pipeline::RenderRunFiles(*result));
  progress.Clear();
  if (!written.ok()) return ReportError(written);
  std::cout << pipeline::RunParameterTable(result->stage.identification)
            << pipeline::IdentificationScreenLine(result->stage.outliers, result->stage.local_defects)
            << pipeline::GapDiagnosisLine(result->diagnosis, result->config.diagnose, result->diagnosis_status);
  std::string times;
  for (const auto& t : result->timings) times += fmt::format(" {} {:.3f}s", t.stage, t.seconds);
  if (progress.on()) Info("stages:" + times);
  if (!a.quiet) Info("wrote " + config->out + "/report.html, result.json, CSV tables and figures/");
  return kExitOk;
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
  sub->add_option("--testpiece", args->overrides.testpiece,
                  "test piece: " + testpieces::PieceNameList() + ", or a tpcal.testpiece/1 YAML (default turning)");
  sub->add_option("--points", args->overrides.points, "measured point file (tpcal points CSV, PLY, PCD, xyz)");
  sub->add_option("--out", args->overrides.out, "output directory (replaced atomically; created if missing)");
  sub->add_option("--machine", args->overrides.machine, "machine YAML (tpcal.machine/1); default: the piece's nominal machine");
  sub->add_option("--truth", args->overrides.truth, "stated truth of a simulated sample (tpcal.sample_truth/1) to mark in the report");
  AddAnchorOption(sub, &args->anchor);
  AddColumnOption(sub, &args->overrides.columns);
  sub->add_option("--parameters", args->overrides.parameters, "coefficients to identify (default: the piece's standard set)")
      ->delimiter(',');
  sub->add_option("--seed", args->overrides.seed, "Monte Carlo seed (default 1), written to every output");
  sub->add_option("--mc-trials", args->overrides.monte_carlo_trials, "GUM S1 Monte Carlo trials (default 2000; 0 = off)");
  sub->add_flag("--keep-outliers", args->overrides.keep_outliers,
               "keep the probe hits and patches the outlier screen flags in identification and diagnosis "
               "(they are still listed); default: left out, with the reason");
  sub->add_option("--reference", args->overrides.reference_file,
                  "an instrument test of the same machine to diagnose against (with --reference-instrument)");
  sub->add_option("--reference-instrument", args->overrides.reference_instrument,
                  "the instrument of --reference: datum_ball (tpcal ballpos v1), probe_artifacts (tpcal probepts v1) "
                  "or ballbar (tpcal ballbar v1); a reference that cannot be read or identified is bad input (exit 2, "
                  "nothing written)");
  sub->add_option("--reference-probe-radius-mm", args->overrides.reference_probe_radius_mm,
                  "the stylus ball radius of a probe_artifacts --reference, mm (default 3)");
  sub->add_option("--reference-setup", args->overrides.reference_setup,
                  "the set-up of --reference: probe_artifacts' artifacts (tpcal.artifacts/1, optional), ballbar's "
                  "installations (tpcal.ballbar_setup/1, required)");
  sub->add_option("--batch", args->batch, "directory or glob of point files: run each, in parallel");
  sub->add_option("-j,--threads", args->threads, "worker threads (0 = all cores)")->capture_default_str();
  sub->add_flag("-q,--quiet", args->quiet, "no progress lines");
  return {sub, [args] { return args->batch.empty() ? RunSingle(*args) : RunBatchCommand(*args); }};
}

}  // namespace tpcal::cli
