// Machine error files (YAML, schema tpcal.errors/1), documented in kinematics/errors_yaml.md.
// Constant parameters flat at the top level with the unit in the key (E_X0C_um: 10,
// E_B(0X)Z_urad: 5, dx_CR(0)_um: 12.4); error motions and drifts as nested maps under `effects:`.
// Unknown keys are errors naming the key and its line.
#pragma once

#include <string>

#include "core/status.h"
#include "kinematics/error_state.h"
#include "kinematics/machine_model.h"

namespace tpcal::kinematics {

Result<ErrorState> LoadErrorState(const std::string& path, const MachineModel& model);
// `source` names the text in messages (file name or "<string>").
Result<ErrorState> ParseErrorState(const std::string& yaml_text, const std::string& source,
                                   const MachineModel& model);
// YAML text that ParseErrorState reads back to the same state (values to 17 significant digits).
std::string FormatErrorState(const ErrorState& errors, const MachineModel& model);

// An error of simulating the machine with the errors read from `path` (a file or "--option"): a
// surface point that does not converge (kNotConverged) means errors far too large, so it is
// located at `path` and says what was expected; any other status is returned unchanged.
Status AtErrorsFile(const Status& status, const std::string& path);

}  // namespace tpcal::kinematics
