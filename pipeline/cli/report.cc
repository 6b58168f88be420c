#include <unistd.h>

#include <atomic>
#include <iostream>

#include "pipeline/cli/commands.h"
#include "pipeline/io/atomic_file.h"

namespace tpcal::cli {
namespace {
std::atomic<bool> g_quiet{false};  // set once by main before any command runs
}

int ReportError(const Status& status) {
  std::cerr << status.ToString() << "\n";
  return kExitBadInput;
}

int WriteJsonOrText(const std::string& json_path, const std::string& json, const std::function<std::string()>& text) {
  if (json_path == "-") {
    std::cout << json;
    return kExitOk;
  }
  std::cout << text();
  if (json_path.empty()) return kExitOk;
  if (Status s = pipeline::WriteFileAtomic(json_path, json); !s.ok()) return ReportError(s);
  Info("wrote " + json_path);
  return kExitOk;
}

void SetQuiet(bool quiet) { g_quiet = quiet; }

void Info(const std::string& line) {
  if (!g_quiet) std::cerr << line << "\n";
}

}  // namespace tpcal::cli
