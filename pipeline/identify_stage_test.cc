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

// A dense file's first pass (the re-alignment only) runs on an even sample. Truth: the same scan
// identified with the first pass on every point (first_pass_points 0). The sample moves the final
// results through the re-association's second-order term and, where cells pool several points,
// through the cells' boundaries (0.14 u on the pipeline_bench scan for a 10 nm shift of the frame).
// Here the circles' points are 2.25 deg apart and a cell spans at most 2 deg, so the cells do not
// pool and the difference is second order (4e-4 u measured; a sample of 3 features gives 0.08 u):
// within 0.02 u, and both within 3 u of the simulated errors. A bad point the sample skips is
// still the file's error, at its line.
TEST(IdentifyStage, DenseFirstPassOnASampleGivesTheSameResult) {
  std::mt19937_64 rng(31);
  const auto truth = RandomTable2(rng);
  testpieces::PieceSimOptions sim_options;
  sim_options.noise_um = 1.0;
  sim_options.seed = 41;
  sim_options.random_placement = true;
  testpieces::ProbingOptions dense;
  dense.points_per_circle = 160;  // 14 faces x 1600 + 16 holes x 800 = 35 200 points
  dense.levels_per_face = 10;
  dense.points_per_hole = 80;
  dense.levels_per_hole = 10;
  sim_options.density = dense;
  auto sim = testpieces::SimulatePiece(Turning(), AcTable(), ToErrorState(truth), sim_options);
  ASSERT_TRUE(sim.ok()) << sim.status().ToString();
  IdentifyStageOptions all;
  all.identify.primary = kinematics::UncertaintyMethod::kAnalytic;
  all.identify.jackknife_groups = false;
  all.scan_cells.above_points = 20000;
  all.first_pass_points = 0;
  IdentifyStageOptions sampled = all;
  sampled.first_pass_points = 5000;
  auto a = RunIdentifyStage(Turning(), AcTable(), sim->points, all);
  auto s = RunIdentifyStage(Turning(), AcTable(), sim->points, sampled);
  ASSERT_TRUE(a.ok()) << a.status().ToString();
  ASSERT_TRUE(s.ok()) << s.status().ToString();
  ASSERT_TRUE(s->scan_cells.has_value());
  EXPECT_EQ(s->scan_cells->num_cells, s->scan_cells->num_points);  // one point per cell
  const auto& pa = a->identification.parameters;
  const auto& ps = s->identification.parameters;
  ASSERT_EQ(pa.size(), ps.size());
  for (std::size_t k = 0; k < pa.size(); ++k) {
    if (!pa[k].identifiable) continue;
    EXPECT_NEAR(ps[k].value, pa[k].value, 0.02 * pa[k].u) << pa[k].name;
    EXPECT_LT(std::abs(ps[k].value - TruthOf(truth, ps[k].name)), 3.0 * ps[k].u) << ps[k].name;
  }

  PointSet bad = sim->points;
  bad.source = "scan.csv";
  bad.line.resize(bad.size());
  for (std::size_t i = 0; i < bad.size(); ++i) bad.line[i] = i + 2;
  bad.feature[1] = PointSet::kUnlabelled;  // not in the sample: every third point of a face
  auto r = RunIdentifyStage(Turning(), AcTable(), bad, sampled);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().ToString().find("scan.csv:3"), std::string::npos) << r.status().ToString();
}

}  // namespace
}  // namespace tpcal::pipeline
