// Post-processor options (YAML, tpcal.gcode/1): gcode::ParseGcodeOptions.
#include "gcode/options_yaml.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tpcal;
  const std::string text(fuzz::AsText(data, size));
  fuzz::CheckStatus(gcode::ParseGcodeOptions(text, "fuzz.yaml").status());
  return 0;
}
