#include "pipeline/cli/diagnose_validate.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <iostream>

#include "pipeline/cli/commands.h"
#include "pipeline/io/atomic_file.h"

namespace tpcal::cli {

void AddValidateOptions(CLI::App* sub, ValidateArgs* args) {
  pipeline::ValidationOptions* v = &args->options;
  sub->add_flag("--validate", args->on, "run the validation on simulated pieces with withheld effects");
  sub->add_option("--trials", v->trials, "validation: trials per family, magnitude and noise level")->capture_default_str();
  sub->add_option("--seed", v->seed, "validation: random seed")->capture_default_str();
  sub->add_option("--magnitudes", v->magnitudes, "validation: peak visible signature / noise sigma")->delimiter(',');
  sub->add_option("--noise", v->noise_um, "validation: CMM noise sigmas (um)")->delimiter(',');
  sub->add_option("--families", v->families, "validation: families to withhold (default all and none)")->delimiter(',');
  sub->add_option("--markdown", args->markdown, "validation: also write the Markdown table here");
  sub->add_flag("--no-placement", args->no_placement, "validation: the CMM frame is the datum frame (no random placement)");
  sub->add_flag("--raw-peak", v->scale_raw_peak,
                "validation: magnitudes scale the raw signature's peak (default: the part the base model cannot absorb)");
  sub->add_option("--reference-noise-um", args->instrument.noise_um,
                  "validation with --reference-instrument datum_ball, probe_artifacts or ballbar: noise sigma of "
                  "the instrument's readings or touches (um)")
      ->capture_default_str();
  args->reference_instrument = sub->get_option_no_throw("--reference-instrument");
}

namespace {

// The instrument --validate is run against ("" = none: the fitted base model).
std::string ValidationInstrument(const ValidateArgs& args) {
  if (args.reference_instrument == nullptr || args.reference_instrument->count() == 0) return "";
  return args.reference_instrument->as<std::string>();
}

}  // namespace

int RunValidate(const ValidateArgs& args, const pipeline::LoadedPiece& setup) {
  pipeline::ValidationOptions options = args.options;
  options.random_placement = !args.no_placement;
  Info(fmt::format("tpcal diagnose --validate: {} piece, seed {}, {} trial(s) per family, magnitude and noise level",
                   setup.piece.name, options.seed, options.trials));
  pipeline::InstrumentValidationOptions instrument = args.instrument;
  instrument.instrument = ValidationInstrument(args);
  if (!instrument.instrument.empty())
    Info(fmt::format("against a {} test of each trial's cold machine, reading noise {:g} um", instrument.instrument,
                     instrument.noise_um));
  auto md = instrument.instrument.empty() ? pipeline::RunValidationStage(setup, options)
                                          : pipeline::RunInstrumentValidationStage(setup, options, instrument);
  if (!md.ok()) return ReportError(md.status());
  std::cout << *md;
  if (!args.markdown.empty()) {
    if (Status s = pipeline::WriteFileAtomic(args.markdown, *md); !s.ok()) return ReportError(s);
    Info("wrote " + args.markdown);
  }
  return kExitOk;
}

}  // namespace tpcal::cli
