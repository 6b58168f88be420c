// Straightness candidates in the ISO 230-1 convention (straightness_lines.h), checked on the
// issue 18 case. Truth: ISO 10791-7 M1 (320) cut on the 3-axis machine with squareness
// E_C(0X)Y = 12, E_B(0X)Z = -16, E_A(0Y)Z = 18 urad and 6 um bows of E_YX and E_XY (cubic through
// 0, 6, 0 um at -160, 0, 160 mm: symmetric, so their reference lines have no slope and the
// squareness truth is unchanged by the convention), CMM noise 0.5 um, random placement, 4 seeds.
// The base model alone is biased by the bows; with the verdict's straightness modelled every
// squareness must lie within 3 u_with of its truth (k = 1, 3 u: 99.7 % two-sided), and u_with
// must exceed u_without (the effect takes information from the squareness).
#include "pipeline/diagnosis/straightness_lines.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "kinematics/errors_yaml.h"
#include "pipeline/diagnosis/diagnosis.h"
#include "testpieces/named_pieces.h"
#include "testpieces/simulate_piece.h"

namespace tpcal::pipeline {
namespace {

TEST(StraightnessLines, ModelledBowsGiveTheIsoSquareness) {
  auto machine = kinematics::MakeMachine(kinematics::MachineType::kXyz);
  ASSERT_TRUE(machine.ok());
  auto named = testpieces::NamedPieceConfig("iso10791_m1");
  ASSERT_TRUE(named.ok());
  auto piece = testpieces::MakeTestPiece(named->config, *machine);
  ASSERT_TRUE(piece.ok()) << piece.status().ToString();
  auto errors = kinematics::ParseErrorState(
      "E_C(0X)Y_urad: 12\nE_B(0X)Z_urad: -16\nE_A(0Y)Z_urad: 18\neffects:\n"
      "  - linear_error_motion: {symbol: E_YX, positions_mm: [-160, 0, 160], values_um: [0, 6, 0], interpolation: cubic}\n"
      "  - linear_error_motion: {symbol: E_XY, positions_mm: [-160, 0, 160], values_um: [0, 6, 0], interpolation: cubic}\n",
      "<test>", *machine);
  ASSERT_TRUE(errors.ok()) << errors.status().ToString();
  const std::map<std::string, double> truth = {{"E_C(0X)Y", 12}, {"E_B(0X)Z", -16}, {"E_A(0Y)Z", 18}};
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    testpieces::PieceSimOptions o;
    o.noise_um = 0.5;
    o.seed = seed;
    o.random_placement = true;
    auto sim = testpieces::SimulatePiece(*piece, *machine, *errors, o);
    ASSERT_TRUE(sim.ok()) << sim.status().ToString();
    auto d = Diagnose(*piece, *machine, sim->points);
    ASSERT_TRUE(d.ok()) << d.status().ToString();
    ASSERT_EQ(d->verdict.family, "linear_straightness") << "seed " << seed;
    const auto& shifts = d->candidates.front().base_shift;
    ASSERT_EQ(shifts.size(), truth.size()) << "seed " << seed;
    for (const auto& s : shifts) {
      EXPECT_LT(std::abs(s.with_um - truth.at(s.name)), 3.0 * s.u_with) << s.name << " seed " << seed;
      EXPECT_GT(s.u_with, s.u_without) << s.name;
    }
  }
}

}  // namespace
}  // namespace tpcal::pipeline
