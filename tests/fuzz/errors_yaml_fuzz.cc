// Machine error files (YAML, tpcal.errors/1): kinematics::ParseErrorState against the bundled
// A/C table machine (even-sized inputs) or B-head/C-table machine (odd-sized).
#include <cstdlib>
#include <map>

#include "kinematics/errors_yaml.h"
#include "kinematics/machine_yaml.h"
#include "tests/fuzz/fuzz_util.h"

namespace {
const tpcal::kinematics::MachineModel& Machine(const char* name) {
  static auto* models = new std::map<std::string, tpcal::kinematics::MachineModel>;
  auto it = models->find(name);
  if (it != models->end()) return it->second;
  auto model = tpcal::kinematics::LoadMachineModel(std::string(TPCAL_SOURCE_DIR) + "/samples/machines/" + name);
  if (!model.ok()) std::abort();
  return models->emplace(name, *model).first->second;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tpcal;
  const std::string text(fuzz::AsText(data, size));
  const auto& model = Machine(size % 2 == 0 ? "ac_table.yaml" : "bhead_ctable.yaml");
  fuzz::CheckStatus(kinematics::ParseErrorState(text, "fuzz.yaml", model).status());
  return 0;
}
