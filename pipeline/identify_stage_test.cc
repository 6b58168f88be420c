// Identification round trips on the seed 002 turning piece: the piece is machined virtually with
// known Table 2 errors (kinematics/simulate.h through testpieces::SimulatePiece, random CMM
// placement), measured, and the stage identifies the errors back from the CMM points alone.
// Truths: random 10-50 um / urad of random sign, std::mt19937_64 with fixed seeds.
// Tolerances: noise-free data must give the truth to 0.05 um / urad (the criterion; the
// exact model is solved, so only solver convergence limits it); noisy data to 3 u (k = 1).
#include "pipeline/identify_stage.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "kinematics/error_parameters.h"
#include "kinematics/machine_model.h"
#include "pipeline/testing/turning_fixture.h"
#include "testpieces/point_association.h"
#include "testpieces/simulate_piece.h"

namespace tpcal::pipeline {
namespace {

using test_support::AcTable;
using test_support::RandomTable2;
using test_support::ToErrorState;
using test_support::Turning;


// Random Table 2 errors: magnitude U(10, 50) um or urad, random sign. Values in display units.
Result<IdentifyStageResult> SimulateAndIdentify(const std::map<std::string, double>& truth, double noise_um,
                                                std::uint64_t seed, const IdentifyStageOptions& options = {}) {
  testpieces::PieceSimOptions sim_options;
  sim_options.noise_um = noise_um;
  sim_options.seed = seed;
  sim_options.random_placement = true;
  auto sim = testpieces::SimulatePiece(Turning(), AcTable(), ToErrorState(truth), sim_options);
  if (!sim.ok()) return sim.status();
  return RunIdentifyStage(Turning(), AcTable(), sim->points, options);
}

double TruthOf(const std::map<std::string, double>& truth, const std::string& name) {
  auto it = truth.find(name);
  if (it == truth.end()) {
    ADD_FAILURE() << "no truth for parameter '" << name << "'";
    return 0.0;
  }
  return it->second;
}

// The truth of an estimable combination: sum coefficient * truth.
double CombinationTruth(const kinematics::Combination& c, const std::map<std::string, double>& truth) {
  double v = 0.0;
  for (std::size_t k = 0; k < c.names.size(); ++k) v += c.coefficients[k] * TruthOf(truth, c.names[k]);
  return v;
}

TEST(IdentifyStage, NoiseFreeRoundTripWithin50nm) {
  std::mt19937_64 rng(20261122);
  for (int trial = 0; trial < 3; ++trial) {
    const auto truth = RandomTable2(rng);
    auto r = SimulateAndIdentify(truth, 0.0, 100 + trial);
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    const auto& id = r->identification;
    // Everything the data determine must come back: identifiable coefficients and the estimable
    // combinations of the others.
    EXPECT_EQ(id.identifiability.num_parameters, 12);  // Table 2 and E_C(0X)Y
    for (const auto& p : id.parameters) {
      if (!p.identifiable) continue;
      EXPECT_NEAR(p.value, TruthOf(truth, p.name), 0.05) << p.name << " trial " << trial;
    }
    for (const auto& combo : id.identifiability.estimable)
      EXPECT_NEAR(combo.value, CombinationTruth(combo, truth), 0.05) << combo.text;
    EXPECT_LT(id.rms_after_um, 1e-3);
  }
}

// A location error of C along X written the ISO 230-1 way (E_X0C, the whole C axis and its table
// 6 um along +X) is seed 002's dx_CR(0) (eq. 1) at every A: A turns about X, so the faces turned
// at A = -90 are centred on the same offset line. Noise-free: dx_CR(0) = 6 um to 0.05 um, every
// other parameter 0, and nothing measurable left over. (With dx_CR(0) active at A = 0 only, this read 3.4 um
// with 7 urad of spurious gamma_CR(-90) and beta_ZX, and left 0.5 um RMS unexplained.)
TEST(IdentifyStage, IsoXPositionOfCIsTable2DxAtEveryA) {
  auto r = SimulateAndIdentify({{"E_X0C", 6.0}}, 0.0, 5);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  for (const auto& p : r->identification.parameters)
    EXPECT_NEAR(p.value, p.name == "dx_CR(0)" ? 6.0 : 0.0, 0.05) << p.name;
  EXPECT_LT(r->identification.rms_after_um, 0.01);  // 2.4 nm left (was 0.5 um)
}

TEST(IdentifyStage, NoisyRoundTripWithin3u) {
  std::mt19937_64 rng(77);
  const double noise_um = 1.0;
  for (int trial = 0; trial < 3; ++trial) {
    const auto truth = RandomTable2(rng);
    auto r = SimulateAndIdentify(truth, noise_um, 300 + trial);
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    const auto& id = r->identification;
    // sigma of the residuals: the CMM noise (n >> q).
    EXPECT_NEAR(id.sigma_um, noise_um, 0.15);
    for (const auto& p : id.parameters) {
      if (!p.identifiable) continue;
      ASSERT_GT(p.u, 0.0) << p.name;
      EXPECT_LT(std::abs(p.value - TruthOf(truth, p.name)), 3.0 * p.u) << p.name << " trial " << trial;
    }
  }
}

// Seed 002 section 5's random 3-of-16 subsets, kept for comparison: on the default plan (points
// spread evenly over each feature) it must give larger u than the jackknife, which the coverage
// study shows to be calibrated; the claim, checked: at least 2x for most coefficients.
TEST(IdentifyStage, RandomSubsetsOverstateTheUncertainty) {
  std::mt19937_64 rng(12);
  const auto truth = RandomTable2(rng);
  IdentifyStageOptions options;
  options.identify.random_subset_trials = 300;
  options.identify.seed = 3;
  auto r = SimulateAndIdentify(truth, 1.0, 600, options);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  int larger = 0, total = 0;
  for (const auto& p : r->identification.parameters) {
    if (!p.identifiable) continue;
    const kinematics::Uncertainty *jk = nullptr, *subsets = nullptr;
    for (const auto& u : p.uncertainties) {
      if (u.method == kinematics::UncertaintyMethod::kJackknifePoints) jk = &u;
      if (u.method == kinematics::UncertaintyMethod::kRandomSubsets) subsets = &u;
    }
    ASSERT_NE(jk, nullptr);
    ASSERT_NE(subsets, nullptr);
    ASSERT_TRUE(subsets->available) << p.name << ": " << subsets->message;
    ++total;
    if (subsets->u > 2.0 * jk->u) ++larger;
  }
  EXPECT_GE(larger, total * 2 / 3) << larger << " of " << total;
}

TEST(IdentifyStage, UnlabelledPointIsAnErrorWithItsLine) {
  std::mt19937_64 rng(1);
  testpieces::PieceSimOptions sim_options;
  auto sim = testpieces::SimulatePiece(Turning(), AcTable(), ToErrorState(RandomTable2(rng)), sim_options);
  ASSERT_TRUE(sim.ok());
  PointSet pts = sim->points;
  pts.source = "cmm.csv";
  auto obs = testpieces::AssociatePoints(Turning(), pts, Rigid3::Identity());
  ASSERT_TRUE(obs.ok());
  pts.feature[3] = PointSet::kUnlabelled;
  auto bad = testpieces::AssociatePoints(Turning(), pts, Rigid3::Identity());
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().ToString().find("cmm.csv"), std::string::npos) << bad.status().ToString();
}

}  // namespace
}  // namespace tpcal::pipeline
