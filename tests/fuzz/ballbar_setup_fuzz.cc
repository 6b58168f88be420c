// Ball-bar set-up files (YAML, tpcal.ballbar_setup/1): kinematics::ParseBallbarSetup. A set it
// reads has unique, non-empty names, nominal lengths > 0 and senses +-1, and FormatBallbarSetup
// writes it back to the same set. Seeds: tests/fuzz/corpus/ballbar_setup/.
#include <set>

#include "kinematics/ballbar_setup.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tpcal;
  const std::string text(fuzz::AsText(data, size));
  auto r = kinematics::ParseBallbarSetup(text, "fuzz.yaml");
  fuzz::CheckStatus(r.status());
  if (!r.ok()) {
    if (r.status().file() != "fuzz.yaml") __builtin_trap();
    return 0;
  }
  std::set<std::string> names;
  for (const auto& i : r->installations)
    if (i.name.empty() || !names.insert(i.name).second || !(i.nominal_length_mm > 0.0) || (i.sense != 1 && i.sense != -1))
      __builtin_trap();
  auto back = kinematics::ParseBallbarSetup(kinematics::FormatBallbarSetup(*r), "fuzz.yaml");
  if (!back.ok() || back->installations.size() != r->installations.size()) __builtin_trap();
  for (std::size_t k = 0; k < r->installations.size(); ++k) {
    const auto &a = r->installations[k], &b = back->installations[k];
    if (a.name != b.name || a.kind != b.kind || a.workpiece_ball_in_part_mm != b.workpiece_ball_in_part_mm ||
        a.tool_ball_in_tool_mm != b.tool_ball_in_tool_mm || a.nominal_length_mm != b.nominal_length_mm ||
        a.sense != b.sense || a.hold_deg != b.hold_deg)
      __builtin_trap();
    if (a.kind == kinematics::BallbarKind::kCircle ? a.plane != b.plane : a.axis != b.axis) __builtin_trap();
  }
  return 0;
}
