#include "pipeline/piece_setup.h"

#include "kinematics/machine_yaml.h"
#include "testpieces/piece_config.h"

namespace tpcal::pipeline {

const std::vector<std::string>& TestPieceNames() {
  static const std::vector<std::string> names = {"turning", "iso10791_m1_160", "iso10791_m1_320", "iso10791_m2",
                                                 "cone_frustum"};
  return names;
}

Result<PieceSetup> LoadPieceSetup(const std::string& name, const std::string& config_path,
                                  const std::string& machine_path) {
  testpieces::PieceConfig config;
  kinematics::MachineType default_machine = kinematics::MachineType::kAcTable;
  if (name == "turning") {
    config.params = testpieces::TurningPieceParams{};
  } else if (name == "iso10791_m1_160") {
    config.params = testpieces::ContourPieceParams::ForSize(160.0);
    default_machine = kinematics::MachineType::kXyz;
  } else if (name == "iso10791_m1_320" || name == "iso10791_m1") {
    config.params = testpieces::ContourPieceParams::ForSize(320.0);
    default_machine = kinematics::MachineType::kXyz;
  } else if (name == "iso10791_m2") {
    config.params = testpieces::FaceMillingPieceParams{};
    default_machine = kinematics::MachineType::kXyz;
  } else if (name == "cone_frustum") {
    config.params = testpieces::ConeFrustumParams{};
  } else {
    std::string list;
    for (const auto& n : TestPieceNames()) list += (list.empty() ? "" : ", ") + n;
    return Status(StatusCode::kInvalidArgument, "unknown test piece '" + name + "' (expected one of: " + list + ")");
  }
  if (!config_path.empty()) {
    auto loaded = testpieces::LoadPieceConfig(config_path);
    if (!loaded.ok()) return loaded.status();
    if (testpieces::KindOf(loaded->params) != testpieces::KindOf(config.params))
      return Status(StatusCode::kInvalidArgument,
                    std::string("the configuration is for the ") + testpieces::PieceKindName(testpieces::KindOf(loaded->params)) +
                        " piece, not " + name,
                    config_path);
    config = std::move(*loaded);
  }
  kinematics::MachineModel machine;
  if (!machine_path.empty()) {
    auto m = kinematics::LoadMachineModel(machine_path);
    if (!m.ok()) return m.status();
    machine = std::move(*m);
  } else {
    auto m = kinematics::MakeMachine(default_machine);
    if (!m.ok()) return m.status();
    machine = std::move(*m);
  }
  auto piece = testpieces::MakeTestPiece(config, machine);
  if (!piece.ok()) return piece.status().WithContext("test piece " + name);
  return PieceSetup{std::move(config), std::move(machine), std::move(*piece)};
}

}  // namespace tpcal::pipeline
