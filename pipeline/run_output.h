// The output directory of `tpcal run`: report.html, result.json, config.yaml (the effective
// configuration), identification.csv, identifiability.csv, characteristics.csv, features.csv
// and figures/<name>.svg.
//
// Atomic as a whole: every file is written (and fsynced) into a fresh sibling directory
// `<out>.tmp.<pid>.<random>`, which then replaces `<out>` by one rename(2) (a new target) or one
// renameat2(RENAME_EXCHANGE) (an existing target, whose old contents are then removed). A crash
// or kill leaves either the old directory or the new one, never a mix or a half-written report;
// at worst a stale `*.tmp.*` sibling, which the next run into the same place removes (its
// process is gone). An existing `<out>` is replaced only if it is empty or
// holds a previous run (a result.json); anything else is refused (kInvalidArgument), so a typo
// in --out cannot wipe an unrelated directory.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/status.h"
#include "pipeline/report/run_report.h"
#include "pipeline/run_stage.h"

namespace tpcal::pipeline {

struct RunFile {
  std::string relative_path;  // "report.html", "figures/machine_errors.svg"
  std::string contents;
};

// What result.json and report.html show of `result` (pointing into it: keep `result` alive).
RunReport ReportOf(const RunResult& result);
RunReport ReportOf(RunResult&& result) = delete;  // the view would point into a temporary

// All files of a run, rendered in memory (deterministic: same result, same bytes).
std::vector<RunFile> RenderRunFiles(const RunResult& result);

// Writes `files` as the directory `out_dir` atomically (see above). Parent directories are
// created. Errors: kIoError naming the path and system call; kInvalidArgument (refused target).
Status WriteDirectoryAtomic(const std::string& out_dir, const std::vector<RunFile>& files);

}  // namespace tpcal::pipeline
