#include "pipeline/cli/progress_line.h"

#include <CLI/CLI.hpp>
#include <unistd.h>

#include <iostream>

namespace tpcal::cli {

void ProgressLine::Show(const std::string& text) const {
  if (on_) std::cerr << "\r\033[K" << text << std::flush;
}

void ProgressLine::Clear() const {
  if (on_) std::cerr << "\r\033[K";
}

bool WantProgress(const CLI::App* root, bool quiet) {
  const bool global_quiet =
      root && root->get_option_no_throw("--quiet") && root->get_option_no_throw("--quiet")->count() > 0;
  return !quiet && !global_quiet && ::isatty(STDERR_FILENO) == 1;
}

}  // namespace tpcal::cli
