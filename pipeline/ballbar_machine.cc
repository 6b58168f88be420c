#include "pipeline/ballbar_machine.h"

#include <algorithm>

#include "kinematics/machine_yaml.h"

namespace tpcal::pipeline {

Result<kinematics::MachineModel> BallbarMachine(const std::string& machine_path,
                                                const kinematics::BallbarSetup& setup) {
  if (!machine_path.empty()) return kinematics::LoadMachineModel(machine_path);
  const bool rotary = std::any_of(setup.installations.begin(), setup.installations.end(),
                                  [](const auto& i) { return i.kind != kinematics::BallbarKind::kCircle; });
  return kinematics::MakeMachine(rotary ? kinematics::MachineType::kBheadCtable : kinematics::MachineType::kXyz);
}

}  // namespace tpcal::pipeline
