// Machine files (YAML, tpcal.machine/1): kinematics::ParseMachineModel.
#include "kinematics/machine_yaml.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tpcal;
  const std::string text(fuzz::AsText(data, size));
  fuzz::CheckStatus(kinematics::ParseMachineModel(text, "fuzz.yaml").status());
  return 0;
}
