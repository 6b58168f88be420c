// tpcal run [PIPELINE.yaml] --batch DIR_OR_GLOB --out DIR [-j N]: every point file, in parallel
// (pipeline/batch.h), with DIR/summary.csv; exit 1 if any file failed.
#include <fmt/format.h>

#include <iostream>
#include <string>

#include "pipeline/batch.h"
#include "pipeline/cli/commands.h"
#include "pipeline/cli/progress_line.h"
#include "pipeline/cli/run_args.h"

namespace tpcal::cli {

int RunBatchCommand(const RunArgs& a) {
  auto config = BuildRunConfig(a, true);
  if (!config.ok()) return ReportError(config.status());
  auto files = pipeline::ExpandBatchInputs(a.batch);
  if (!files.ok()) return ReportError(files.status());
  pipeline::BatchOptions options;
  options.base = *config;
  options.out_dir = config->out;
  options.threads = a.threads;
  const ProgressLine progress(WantProgress(a.root, a.quiet));
  auto on_item = [&progress](const pipeline::BatchItem& item, std::size_t done, std::size_t total) {
    if (!item.status.ok()) {
      progress.Clear();
      std::cerr << "FAILED " << item.status.ToString() << "\n";
    }
    progress.Show(fmt::format("tpcal run --batch: {}/{} {}", done, total, item.points));
  };
  auto result = pipeline::RunBatch(*files, options, on_item);
  progress.Clear();
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

}  // namespace tpcal::cli
