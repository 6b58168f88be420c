#include "pipeline/diagnosis/diagnosis_verdict.h"

#include <gtest/gtest.h>

#include <Eigen/QR>
#include <cmath>
#include <random>
#include <vector>

#include "kinematics/machine_model.h"
#include "pipeline/diagnosis/diagnosis_least_squares.h"
#include "pipeline/diagnosis/diagnosis_projection.h"

namespace tpcal::pipeline::diagnosis_internal {
namespace {

// The excess test against a reference whose leftover uncertainty is as large as the split lets it
// be: n = 120 residuals (nothing fitted), noise sigma 1 um, the reference's factor R on 60
// orthonormal directions at sigma each (eigenvalues sigma^2, the split's threshold). The neighbour
// sigma is drawn from its own law (sigma^2 chi2_m / m, m = 0.37 n, the MAD's degrees of freedom
// the test assumes). Truth: every draw is noise and reference alone, so a nominal 1 % test should
// reject about 1 %. Taking the reference's variance off by its mean ((SSR - tr A) / n sigma^2 on
// n) ignores that its part adds half again to the spread of SSR. 20 000 draws (seed 11), binomial
// sd of a 1 % rate 0.07 %: the law rejects 1.31 % (the Satterthwaite and Paulson approximations
// about 0.3 %), the mean taken off 1.80 %.
TEST(ExcessTest, WeighsTheReferencesSpreadNotOnlyItsMean) {
  constexpr int n = 120, r = 60, draws = 20000;
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd G(n, r);
  for (Eigen::Index i = 0; i < G.size(); ++i) G(i) = normal(rng);
  const Eigen::MatrixXd R = Eigen::HouseholderQR<Eigen::MatrixXd>(G).householderQ() * Eigen::MatrixXd::Identity(n, r);
  auto machine = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  ASSERT_TRUE(machine.ok());
  BaseFit fit{kinematics::ErrorState(*machine)};
  fit.reference_remaining_um = R;
  fit.reference_var_um2 = R.rowwise().squaredNorm();
  const CandidateCatalogue catalogue;
  const ScoredCandidates scored;
  const DiagnosisOptions options;  // alpha 1 %
  const double m = 0.37 * n;
  std::chi_squared_distribution<double> mad_law(m);
  BaseGap gap{Eigen::VectorXd(n), Eigen::VectorXd::Zero(n), 0.0, 0.0, 0.0,
              GroupCrossValidation(Eigen::MatrixXd(n, 0), std::vector<int>(n, 0), 1, 1e-9), GroupCvResult{}, {}};
  int rejected = 0, rejected_mean_only = 0;
  for (int draw = 0; draw < draws; ++draw) {
    Eigen::VectorXd w(r);
    for (int i = 0; i < n; ++i) gap.r(i) = normal(rng);
    for (int j = 0; j < r; ++j) w(j) = normal(rng);
    gap.r += R * w;
    gap.ssr = gap.r.squaredNorm();
    DiagnosisResult out;
    out.neighbour_sigma_um = std::sqrt(mad_law(rng) / m);
    CompleteVerdict({catalogue, scored, fit, gap, options, {}}, &out);
    rejected += out.excess_p_value < 0.01;
    const double s2 = out.neighbour_sigma_um * out.neighbour_sigma_um;
    rejected_mean_only += FUpperTail(std::max(0.0, gap.ssr - r) / n / s2, n, m) < 0.01;
  }
  const double rate = static_cast<double>(rejected) / draws, mean_only = static_cast<double>(rejected_mean_only) / draws;
  EXPECT_NEAR(rate, 0.01, 0.004) << "mean only: " << mean_only;
  EXPECT_GT(mean_only, rate + 0.003) << "law: " << rate;
}

// FBeyond remembers each test in the inputs' memo, and what it remembers is what it computes.
// n = 200 residuals of unit noise (seed 5) plus 3 x candidate j's column (entries of unit RMS),
// over a base of the constant column; candidate k is a sine the gap does not hold. Truth: j
// beyond k has F near 9 n / 1 = 1800 on (1, 197) (p below 1e-12 by far); k beyond j is F(1, 197)
// noise (below 12, its 0.07 % point, for this seed).
TEST(FBeyondTest, EachTestIsComputedOnceAndRemembered) {
  constexpr int n = 200;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  auto machine = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  ASSERT_TRUE(machine.ok());
  BaseFit fit{kinematics::ErrorState(*machine)};
  fit.basis.U = Eigen::MatrixXd::Constant(n, 1, 1.0 / std::sqrt(double{n}));
  fit.basis.rank = 1;
  CandidateCatalogue catalogue;
  Eigen::VectorXd cj(n), ck(n), r(n);
  for (int i = 0; i < n; ++i) {
    cj(i) = std::sqrt(2.0) * std::cos(0.1 * i);
    ck(i) = std::sqrt(2.0) * std::sin(0.37 * i);
    r(i) = normal(rng) + 3.0 * cj(i);
  }
  for (const auto& c : {cj, ck}) catalogue.candidates.push_back({"f", "c", c, {"p"}, {"um"}, nullptr, {}});
  const DiagnosisOptions options;
  ScoredCandidates scored;
  for (const auto& c : catalogue.candidates)
    scored.bases.push_back(ProjectCandidate(ColumnsOf(c), fit.basis.U, options.absorbed_tolerance));
  BaseGap gap{r, Eigen::VectorXd::Zero(n), r.squaredNorm(), 0.0, 0.0,
              GroupCrossValidation(Eigen::MatrixXd(n, 0), std::vector<int>(n, 0), 1, 1e-9), GroupCvResult{}, {}};
  const VerdictInputs in{catalogue, scored, fit, gap, options, {}};
  const auto j_beyond_k = FBeyond(in, 0, 1);
  EXPECT_GT(j_beyond_k.first, 1000.0);
  EXPECT_LT(j_beyond_k.second, 1e-12);
  EXPECT_EQ(in.f_beyond.size(), 1u);
  const auto k_beyond_j = FBeyond(in, 1, 0);
  EXPECT_LT(k_beyond_j.first, 12.0);
  EXPECT_EQ(in.f_beyond.size(), 2u);
  EXPECT_EQ(FBeyond(in, 0, 1), j_beyond_k);
  EXPECT_EQ(in.f_beyond.size(), 2u);
  const VerdictInputs fresh{catalogue, scored, fit, gap, options, {}};
  EXPECT_EQ(FBeyond(fresh, 1, 0), k_beyond_j);
}

}  // namespace
}  // namespace tpcal::pipeline::diagnosis_internal
