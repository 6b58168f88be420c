// Pipeline files (YAML, tpcal.pipeline/1): pipeline::ParsePipelineConfig.
#include "pipeline/run_config.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tpcal;
  const std::string text(fuzz::AsText(data, size));
  fuzz::CheckStatus(pipeline::ParsePipelineConfig(text, "fuzz.yaml").status());
  return 0;
}
