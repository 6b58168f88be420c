// The tpcal command table: each subcommand registers its options on the CLI11 app and returns
// the function that runs it after parsing. Subcommands are thin: parse, validate, call library
// code, write outputs atomically, choose the exit code. Only this layer prints.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/status.h"

namespace CLI {
class App;
}

namespace tpcal::cli {

// Exit codes of every tpcal command.
inline constexpr int kExitOk = 0;          // success
inline constexpr int kExitSomeFailed = 1;  // a batch ran, but some items failed
inline constexpr int kExitBadInput = 2;    // bad input or usage: nothing was written

struct Command {
  CLI::App* app = nullptr;    // the subcommand
  std::function<int()> run;   // runs it after a successful parse
};

using Registrar = Command (*)(CLI::App& app);

// Each command's options on `app` (its <name>_command.cc).
Command RegisterFit(CLI::App& app);
Command RegisterPlan(CLI::App& app);
Command RegisterSimulate(CLI::App& app);
Command RegisterGcode(CLI::App& app);
Command RegisterIdentify(CLI::App& app);
Command RegisterDiagnose(CLI::App& app);
Command RegisterRun(CLI::App& app);

// The command table, in --help order: fit, plan, simulate, gcode, identify, diagnose, run.
const std::vector<Registrar>& CommandTable();

// Prints "file:line: message" to stderr and returns kExitBadInput.
int ReportError(const Status& status);
// `json_path` "-": the JSON on stdout; otherwise the text (made only then) on stdout and, for a
// non-empty path, the JSON written there atomically ("wrote PATH"). kExitOk, or the write error's
// exit code after reporting it.
int WriteJsonOrText(const std::string& json_path, const std::string& json, const std::function<std::string()>& text);
// Prints a progress/info line to stderr unless quiet.
void Info(const std::string& line);
void SetQuiet(bool quiet);

}  // namespace tpcal::cli
