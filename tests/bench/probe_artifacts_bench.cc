// Speed of the probing test of artifacts (kinematics/probe_artifact_identification.h): seed 000's
// 4 x 6-pose plan (A 0, -30, -60, -90 deg, C every 60 deg; the 266 touches the probe reaches on
// its three columns, testpieces/probe_artifacts_plan.h) under location errors and error motions
// with 0.3 um probe noise (seed 3): the 24 table poses with their covariance, then the 168 map
// entries. Baseline measured in the same run: the virtual touches of the same plan (one Newton
// contact per touch), the least a simulated test costs. Issue 20 target: < 100 ms.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <random>
#include <vector>

#include "core/portable_random.h"
#include "kinematics/errors_yaml.h"
#include "kinematics/probe_artifact_identification.h"
#include "kinematics/probe_touch.h"
#include "testpieces/probe_artifacts_plan.h"

namespace {

using namespace tpcal;

struct PaCase {
  kinematics::MachineModel machine;
  kinematics::ErrorState truth;
  testpieces::ProbeArtifactsPlan plan;
  std::vector<kinematics::ProbeTouch> touches;
};

const PaCase& Test4x6() {
  static const PaCase c = [] {
    auto m = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
    auto e = kinematics::ParseErrorState(
        "E_X0C_um: 10\nE_Y0C_um: -6\nE_B0C_urad: 25\nE_Y0A_um: 8\nE_C0A_urad: -15\n"
        "effects:\n"
        "  - rotary_error_motion: {symbol: E_AA, positions_deg: [-90, 0], values_urad: [35, 0], periodic: false}\n"
        "  - rotary_error_motion: {symbol: E_XC, harmonics: [{order: 2, cos_um: 1.5, sin_um: -0.8}]}\n",
        "<bench>", *m);
    if (!m.ok() || !e.ok()) {
      std::fprintf(stderr, "probe_artifacts_bench: setup failed\n");
      std::exit(1);
    }
    auto plan = testpieces::MakeProbeArtifactsPlan(*m, kinematics::Seed000Artifacts());
    if (!plan.ok()) std::exit(1);
    std::mt19937_64 rng(3);
    std::vector<kinematics::ProbeTouch> touches;
    for (const testpieces::PlannedTouch& t : plan->touches) {
      const kinematics::FaceGeometry g = kinematics::FaceOf(plan->artifacts.boxes[t.artifact], t.face);
      auto contact = kinematics::SimulateTouch(*m, *e, t.rotary, g, t.target_part_mm, {});
      if (!contact.ok()) std::exit(1);
      kinematics::ProbeTouch touch;
      touch.rotary = t.rotary;
      touch.artifact = t.artifact;
      touch.face = t.face;
      touch.approach = t.approach;
      touch.contact_mm = *contact + 0.3e-3 * StandardNormal(rng) * t.approach;
      touches.push_back(touch);
    }
    return PaCase{*m, *e, *plan, touches};
  }();
  return c;
}

void BM_VirtualTouchPass(benchmark::State& state) {
  const PaCase& c = Test4x6();
  for (auto _ : state)
    for (const testpieces::PlannedTouch& t : c.plan.touches)
      benchmark::DoNotOptimize(kinematics::SimulateTouch(
          c.machine, c.truth, t.rotary, kinematics::FaceOf(c.plan.artifacts.boxes[t.artifact], t.face), t.target_part_mm, {}));
}
BENCHMARK(BM_VirtualTouchPass)->Unit(benchmark::kMillisecond);

void BM_Identify4x6(benchmark::State& state) {
  const PaCase& c = Test4x6();
  for (auto _ : state) {
    auto r = kinematics::IdentifyProbeArtifacts(c.machine, c.plan.artifacts, c.touches);
    if (!r.ok()) state.SkipWithError("identification failed");
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_Identify4x6)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
