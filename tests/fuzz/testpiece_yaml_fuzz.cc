// Test-piece configurations (YAML, tpcal.testpiece/1): testpieces::ParsePieceConfig.
#include "testpieces/piece_config.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tpcal;
  const std::string text(fuzz::AsText(data, size));
  fuzz::CheckStatus(testpieces::ParsePieceConfig(text, "fuzz.yaml").status());
  return 0;
}
