// Process-effect files (`tpcal simulate --process P.yaml`, schema tpcal.process/1): the cutting-
// force deflection and servo-reversal models of process_effects.h, so simulated pieces can carry
// the effects that are not machine geometry (the diagnosis's tool_deflection and servo_reversal
// families). Keys are the model fields with their units; an absent section is no effect, an
// absent key its default. Unknown or duplicate keys, wrong types and invalid values are
// kParseError / kInvalidArgument "file:line: what was expected".
//
//   schema: tpcal.process/1
//   tool_deflection:                   # process_effects.h ToolDeflectionModel
//     specific_force_n_per_mm2: 2000   # Kc
//     passive_ratio: 0.4               # Fp / Fc
//     feed_ratio: 0.3                  # Ff / Fc
//     floor_axial_area_mm2: 0.02
//     compliance_um_per_n: [0.02, 0.025, 0.01]   # tool side, machine X, Y, Z
//     scale: 1
//   servo_reversal:                    # ServoReversalModel, circular interpolation in X-Y
//     spike_x_um: 4                    # quadrant glitch height when X reverses (outward)
//     spike_y_um: 4
//     decay_deg: 4
//     backlash_x_um: 0                 # lost motion (full value)
//     backlash_y_um: 0
#pragma once

#include <string>
#include <string_view>

#include "core/status.h"
#include "testpieces/process_effects.h"

namespace tpcal::testpieces {

// `source` names the text in messages.
Result<ProcessEffects> ParseProcessEffects(std::string_view yaml_text, const std::string& source);
// Reads and parses a file (kIoError if it cannot be read).
Result<ProcessEffects> LoadProcessEffects(const std::string& path);
// YAML that ParseProcessEffects reads back to the same effects (17 significant digits); every key
// of a present section, "{}" when there is no effect.
std::string FormatProcessEffects(const ProcessEffects& effects);

}  // namespace tpcal::testpieces
