// Artifact files (YAML, tpcal.artifacts/1): kinematics::ParseArtifactsYaml. A set it reads has
// unique, non-empty names and positive sizes, and FormatArtifactsYaml writes it back to the same
// set. Seeds: tests/fuzz/corpus/artifacts_yaml/.
#include <set>

#include "kinematics/artifacts_yaml.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tpcal;
  const std::string text(fuzz::AsText(data, size));
  auto r = kinematics::ParseArtifactsYaml(text, "fuzz.yaml");
  fuzz::CheckStatus(r.status());
  if (!r.ok()) {
    if (r.status().file() != "fuzz.yaml") __builtin_trap();
    return 0;
  }
  std::set<std::string> names;
  for (const auto& b : r->boxes)
    if (b.name.empty() || !names.insert(b.name).second || !(b.size_mm.minCoeff() > 0.0)) __builtin_trap();
  auto back = kinematics::ParseArtifactsYaml(kinematics::FormatArtifactsYaml(*r), "fuzz.yaml");
  if (!back.ok() || back->boxes.size() != r->boxes.size()) __builtin_trap();
  for (std::size_t i = 0; i < r->boxes.size(); ++i) {
    const auto &a = r->boxes[i], &b = back->boxes[i];
    if (a.name != b.name || a.base_centre_mm != b.base_centre_mm || a.size_mm != b.size_mm ||
        a.rotation_deg != b.rotation_deg)
      __builtin_trap();
  }
  return 0;
}
