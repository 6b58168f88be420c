// The options of `tpcal run` (run_command.cc registers them) and what both of its modes share:
// one point file (run_command.cc) or a batch of them (run_batch_command.cc). CLI layer only.
#pragma once

#include <string>

#include "core/status.h"
#include "pipeline/run_config.h"

namespace CLI {
class App;
}

namespace tpcal::cli {

struct RunArgs {
  std::string pipeline;                   // PIPELINE.yaml; "" = the defaults
  pipeline::PipelineOverrides overrides;  // the flags over it
  std::string anchor;  // FEATURE@X,Y,Z: overrides raw_scan.anchor_feature / anchor_near_mm
  std::string batch;   // directory or glob of point files
  int threads = 0;
  bool quiet = false;  // the subcommand's -q
  CLI::App* root = nullptr;
};

// The pipeline file (or the defaults), then --anchor, then the flags over them
// (pipeline::ApplyPipelineOverrides). Errors: the file's, --anchor's, then the overrides'.
Result<pipeline::PipelineConfig> BuildRunConfig(const RunArgs& args, bool batch);

// `tpcal run --batch`: exit code kExitOk, kExitSomeFailed or kExitBadInput.
int RunBatchCommand(const RunArgs& args);

}  // namespace tpcal::cli
