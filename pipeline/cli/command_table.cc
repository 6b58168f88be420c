#include "pipeline/cli/commands.h"

namespace tpcal::cli {

const std::vector<Registrar>& CommandTable() {
  static const std::vector<Registrar> table = {RegisterFit,     RegisterPlan,     RegisterSimulate, RegisterGcode,
                                               RegisterIdentify, RegisterDiagnose, RegisterRun};
  return table;
}

}  // namespace tpcal::cli
