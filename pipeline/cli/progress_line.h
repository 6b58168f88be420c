// One self-overwriting progress line on stderr ("\r\033[K" then the text, no newline), for
// `tpcal run`: shown only on a terminal and never with -q. CLI layer only.
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace tpcal::cli {

class ProgressLine {
 public:
  explicit ProgressLine(bool on) : on_(on) {}
  bool on() const { return on_; }
  void Show(const std::string& text) const;  // replaces the line; nothing when off
  void Clear() const;                        // erases it; nothing when off

 private:
  bool on_;
};

// True when stderr is a terminal and neither the global -q (on `root`) nor the subcommand's
// `quiet` was given.
bool WantProgress(const CLI::App* root, bool quiet);

}  // namespace tpcal::cli
