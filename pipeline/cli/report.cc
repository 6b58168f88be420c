#include <unistd.h>

#include <atomic>
#include <iostream>

#include "pipeline/cli/commands.h"

namespace tpcal::cli {
namespace {
std::atomic<bool> g_quiet{false};  // set once by main before any command runs
}

int ReportError(const Status& status) {
  std::cerr << status.ToString() << "\n";
  return kExitBadInput;
}

void SetQuiet(bool quiet) { g_quiet = quiet; }

void Info(const std::string& line) {
  if (!g_quiet) std::cerr << line << "\n";
}

}  // namespace tpcal::cli
