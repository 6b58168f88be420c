#include "pipeline/diagnosis/diagnosis_verdict.h"

#include <gtest/gtest.h>

#include <Eigen/QR>
#include <cmath>
#include <random>
#include <vector>

#include "kinematics/machine_model.h"
#include "pipeline/diagnosis/diagnosis_least_squares.h"

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
    CompleteVerdict({catalogue, scored, fit, gap, options}, &out);
    rejected += out.excess_p_value < 0.01;
    const double s2 = out.neighbour_sigma_um * out.neighbour_sigma_um;
    rejected_mean_only += FUpperTail(std::max(0.0, gap.ssr - r) / n / s2, n, m) < 0.01;
  }
  const double rate = static_cast<double>(rejected) / draws, mean_only = static_cast<double>(rejected_mean_only) / draws;
  EXPECT_NEAR(rate, 0.01, 0.004) << "mean only: " << mean_only;
  EXPECT_GT(mean_only, rate + 0.003) << "law: " << rate;
}

}  // namespace
}  // namespace tpcal::pipeline::diagnosis_internal
