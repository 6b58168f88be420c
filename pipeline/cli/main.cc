// tpcal: calibrate machine tools from machined test pieces. See README.md.
#include <CLI/CLI.hpp>

#include <iostream>
#include <vector>

#include "core/allocator.h"
#include "pipeline/cli/commands.h"
#include "pipeline/version.h"

int main(int argc, char** argv) {
  tpcal::KeepFreedMemoryForReuse();  // dense scans reuse freed blocks (core/allocator.h)
  using namespace tpcal::cli;
  CLI::App app{
      "tpcal " + std::string(tpcal::kVersion) +
      ": calibrate machine tools from machined test pieces.\n"
      "A machine cuts a test piece, a CMM measures it, tpcal says what is wrong with the machine.\n"
      "Lengths in mm and angles in deg/rad inside files as their column names say; reports in um and urad.\n"
      "Exit codes: 0 success, 1 some batch items failed, 2 bad input or usage."};
  app.set_version_flag("--version", std::string("tpcal ") + tpcal::kVersion + " (" + tpcal::kGitRevision + ")");
  app.require_subcommand(1);
  bool quiet = false;
  app.add_flag("-q,--quiet", quiet, "no progress lines on stderr");

  std::vector<Command> commands;
  for (Registrar reg : CommandTable()) {
    if (Command c = reg(app); c.app != nullptr) commands.push_back(c);
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return kExitBadInput;
  }
  SetQuiet(quiet);
  for (const Command& c : commands) {
    if (c.app->parsed()) {
      try {
        return c.run();
      } catch (const std::exception& e) {
        std::cerr << "tpcal: internal error: " << e.what() << "\n";
        return kExitBadInput;
      }
    }
  }
  return kExitBadInput;
}
