// Batch runs of the pipeline (`tpcal run --batch DIR_OR_GLOB`): many point files with one
// configuration, in parallel on the shared pool of core/parallel.h. A file that fails (unreadable, corrupt, a
// feature with too few points, an identification that fails) is recorded with its error and the
// batch goes on. Each good file gets its own run directory `<out>/<stem>/` (run_output.h); the
// batch writes `<out>/summary.csv` (one row per file, in input order: status, error, and every
// machine error with its u, so a spreadsheet trends each error across runs) and
// `<out>/summary_trend.svg` (each identified error against the run index, with 95 % intervals).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/status.h"
#include "kinematics/identification.h"
#include "pipeline/run_config.h"
#include "pipeline/run_stage.h"

namespace tpcal::pipeline {

// The point files of `dir_or_glob`: a directory gives its regular files with a point-file
// extension (.csv .ply .pcd .xyz .txt), not recursing; otherwise a glob(3) pattern (its matches
// that are regular files). Sorted by path. Errors: kInvalidArgument if nothing matches.
Result<std::vector<std::string>> ExpandBatchInputs(const std::string& dir_or_glob);

struct BatchOptions {
  PipelineConfig base;  // everything but `points` (and `out`, see out_dir)
  std::string out_dir;  // batch output directory (run directories and the summary)
  int threads = 0;      // threads in all, nested loops included; 0 = the cores
  bool write_runs = true;  // write each file's run directory (else only the summary)
};

struct BatchItem {
  std::string points;
  std::string run_dir;  // "" when not written
  Status status;        // OK, or why this file failed
  std::size_t num_points = 0;
  double rms_after_um = 0.0;
  double sigma_um = 0.0;
  std::vector<kinematics::ParameterEstimate> parameters;  // empty on failure
  double seconds = 0.0;
};

struct BatchResult {
  std::vector<BatchItem> items;  // input order
  int failed = 0;
};

// Called from worker threads (serialised by the batch) after each file, with the count done.
using BatchItemFn = std::function<void(const BatchItem& item, std::size_t done, std::size_t total)>;

// Runs every file. Never fails as a whole on a bad file; errors of the batch output itself
// (summary not writable) come back as the status.
Result<BatchResult> RunBatch(const std::vector<std::string>& files, const BatchOptions& options,
                             const BatchItemFn& on_item = {});

// summary.csv: file,status,error,num_points,rms_after_um,sigma_um, then per parameter
// `<name>_<unit>` and `<name>_u_<unit>` (empty when failed or not identifiable).
std::string BatchSummaryCsv(const BatchResult& result);
// summary_trend.svg; nullopt-like empty string when no file succeeded.
std::string BatchTrendSvg(const BatchResult& result);

}  // namespace tpcal::pipeline
