// Inspection plans (YAML): gdt::ParseInspectionPlan.
#include "gdt/plan_yaml.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tpcal;
  const std::string text(fuzz::AsText(data, size));
  fuzz::CheckStatus(gdt::ParseInspectionPlan(text, "fuzz.yaml").status());
  return 0;
}
