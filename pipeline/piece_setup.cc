#include "pipeline/piece_setup.h"

#include "kinematics/machine_yaml.h"
#include "testpieces/named_pieces.h"
#include "testpieces/piece_config.h"

namespace tpcal::pipeline {

Result<PieceSetup> LoadPieceSetup(const std::string& name, const std::string& config_path,
                                  const std::string& machine_path) {
  auto named = testpieces::NamedPieceConfig(name);
  if (!named.ok()) return named.status();
  testpieces::PieceConfig config = named->config;
  if (!config_path.empty()) {
    auto loaded = testpieces::LoadPieceConfig(config_path);
    if (!loaded.ok()) return loaded.status();
    if (Status s = testpieces::CheckConfigMatchesName(*loaded, *named, name, config_path); !s.ok()) return s;
    config = std::move(*loaded);
  }
  kinematics::MachineModel machine;
  if (!machine_path.empty()) {
    auto m = kinematics::LoadMachineModel(machine_path);
    if (!m.ok()) return m.status();
    machine = std::move(*m);
  } else {
    auto m = kinematics::MakeMachine(named->usual_machine);
    if (!m.ok()) return m.status();
    machine = std::move(*m);
  }
  auto piece = testpieces::MakeTestPiece(config, machine);
  if (!piece.ok()) return piece.status().WithContext("test piece " + name);
  return PieceSetup{std::move(config), std::move(machine), std::move(*piece)};
}

}  // namespace tpcal::pipeline
