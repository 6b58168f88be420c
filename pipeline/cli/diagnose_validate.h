// `tpcal diagnose --validate`: the option group (--validate, --trials, --seed, --magnitudes,
// --noise, --families, --markdown, --no-placement, --raw-peak, --reference-noise-um) and its run,
// the validation on simulated pieces with withheld effects (pipeline/diagnose_stage.h); with the
// diagnosis's --reference-instrument, against that instrument's test of each trial's cold machine
// (pipeline/instrument_validation.h). CLI layer only.
#pragma once

#include <string>

#include "pipeline/diagnose_stage.h"
#include "pipeline/instrument_validation.h"

namespace CLI {
class App;
class Option;
}  // namespace CLI

namespace tpcal::cli {

struct ValidateArgs {
  bool on = false;               // --validate
  pipeline::ValidationOptions options;
  bool no_placement = false;     // --no-placement: options.random_placement = false
  std::string markdown;          // also write the Markdown here
  pipeline::InstrumentValidationOptions instrument;  // --reference-noise-um
  // The diagnosis's --reference-instrument (added before this group), read at run time; may be null.
  const CLI::Option* reference_instrument = nullptr;
};

// Adds the group to `sub` (after the diagnosis options: --help lists them last).
void AddValidateOptions(CLI::App* sub, ValidateArgs* args);

// Prints the validation's Markdown on stdout (and writes it to --markdown). Exit code.
int RunValidate(const ValidateArgs& args, const pipeline::LoadedPiece& setup);

}  // namespace tpcal::cli
