// Identification under random CMM placement (the part anywhere, in any orientation on the CMM)
// for every ISO piece: the datum frame each inspection plan builds from measured features must
// recover the nominal datum frame, so the association (testpieces::CutPointAtDatum) finds the
// cut of every point and the residuals are the CMM noise alone.
// Truths: small location errors (a few um / urad, model of the piece's default machine), noise
// 0.5 um, several placement seeds. Tolerance: residual sigma within 0.15 um of the noise (n >> q).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "kinematics/error_parameters.h"
#include "kinematics/error_state.h"
#include "pipeline/identify_stage.h"
#include "pipeline/piece_loader.h"
#include "testpieces/default_parameters.h"
#include "testpieces/simulate_piece.h"

namespace tpcal::pipeline {
namespace {

constexpr double kNoise_um = 0.5;
constexpr double kSigmaTol_um = 0.15;  // sample sigma of a few hundred residuals, q << n

// Every parameter of the piece's default identification set at a small value (5, 8, 11 ...
// um or urad, alternating sign; a polynomial error-motion coefficient "E_ZX.cP" such that the
// term reaches that value at 100 mm of axis travel).
Result<kinematics::ErrorState> SmallLocationErrors(const LoadedPiece& setup) {
  kinematics::ErrorState errors(setup.machine);
  const auto names = testpieces::DefaultParameterSet(setup.piece, setup.machine);
  auto active = kinematics::ActivateParameters(setup.machine, &errors, names);
  if (!active.ok()) return active.status();
  for (std::size_t k = 0; k < names.size(); ++k) {
    const double display = (k % 2 ? -1.0 : 1.0) * (5.0 + 3.0 * static_cast<double>(k % 5));  // um or urad
    const int c = active->coefficients[k];
    if (auto info = kinematics::LookupParameter(setup.machine, names[k]); info.ok()) {
      const double internal = display * (info->quantity == kinematics::Quantity::kAngle ? 1e-6 : 1e-3);
      if (Status s = errors.SetParameter(setup.machine, names[k], internal); !s.ok()) return s;
    } else {
      const int power = std::stoi(names[k].substr(names[k].rfind(".c") + 2));
      errors.set_coefficient(c, display * 1e-3 / std::pow(100.0, power));  // mm per mm^power
    }
  }
  return errors;
}

struct Case {
  std::string piece;
  std::string machine;  // samples/machines/<machine>.yaml, or "" for the piece's default machine
};

class DatumPlacement : public ::testing::TestWithParam<Case> {};

TEST_P(DatumPlacement, IdentifiesUnderRandomPlacement) {
  const std::string name = GetParam().piece;
  const std::string machine =
      GetParam().machine.empty() ? "" : std::string(TPCAL_SOURCE_DIR) + "/samples/machines/" + GetParam().machine + ".yaml";
  auto setup = LoadPiece({.testpiece = name, .machine_path = machine});
  ASSERT_TRUE(setup.ok()) << setup.status().ToString();
  auto errors = SmallLocationErrors(*setup);
  ASSERT_TRUE(errors.ok()) << errors.status().ToString();
  for (std::uint64_t seed : {1u, 2u, 3u, 4u}) {
    testpieces::PieceSimOptions o;
    o.noise_um = kNoise_um;
    o.seed = seed;
    o.random_placement = true;
    auto sim = testpieces::SimulatePiece(setup->piece, setup->machine, *errors, o);
    ASSERT_TRUE(sim.ok()) << sim.status().ToString();
    auto stage = RunIdentifyStage(setup->piece, setup->machine, sim->points);
    ASSERT_TRUE(stage.ok()) << name << " seed " << seed << ": " << stage.status().ToString();
    EXPECT_NEAR(stage->identification.sigma_um, kNoise_um, kSigmaTol_um) << name << " seed " << seed;
  }
}

INSTANTIATE_TEST_SUITE_P(IsoPieces, DatumPlacement,
                         ::testing::Values(Case{"iso10791_m1_160", ""}, Case{"iso10791_m2", "bc_table"},
                                           Case{"cone_frustum", ""}),
                         [](const auto& info) { return info.param.piece; });

}  // namespace
}  // namespace tpcal::pipeline
