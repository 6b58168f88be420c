#include "pipeline/diagnosis/diagnosis_least_squares.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <utility>

namespace tpcal::pipeline::diagnosis_internal {
namespace {

// Without a correlated part the law is the plain chi-square: mean k sigma^2, k degrees of freedom.
// With Z = I (k = 2, sigma^2 = 1) the sum is 2 chi2_2: mean 4, d = 2. Exact arithmetic.
TEST(SatterthwaiteLaw, ReducesToTheChiSquareOfItsParts) {
  const ChiSquareLaw plain = SatterthwaiteLaw(3, 0.25, Eigen::MatrixXd(3, 0));
  EXPECT_DOUBLE_EQ(plain.mean_um2, 0.75);
  EXPECT_DOUBLE_EQ(plain.dof, 3.0);
  const ChiSquareLaw doubled = SatterthwaiteLaw(2, 1.0, Eigen::MatrixXd::Identity(2, 2));
  EXPECT_DOUBLE_EQ(doubled.mean_um2, 4.0);
  EXPECT_DOUBLE_EQ(doubled.dof, 2.0);
}

// A sum of squares Q of k = 4 components, noise of sigma^2 = 0.25 um^2 each and a correlated part
// Z Z^T, drawn `draws` times (seed 7): its sample mean and variance, and how often a nominal 1 %
// test rejects it, by its law (Q / mean on (d, infinity)) and by the mean taken off ((Q - tr A) /
// (k sigma^2) on k degrees of freedom: the spread ignored).
struct Draws {
  ChiSquareLaw law;
  double mean_um2 = 0.0, var_um4 = 0.0, rate = 0.0, rate_mean_only = 0.0;
};
Draws DrawSums(const Eigen::MatrixXd& Z, double sigma2_um2, int draws) {
  const auto k = static_cast<int>(Z.rows());
  Draws out;
  out.law = SatterthwaiteLaw(k, sigma2_um2, Z);
  const double tr_a = Z.squaredNorm();
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  double sum = 0.0, sum2 = 0.0;
  int rejected = 0, rejected_mean_only = 0;
  for (int draw = 0; draw < draws; ++draw) {
    Eigen::VectorXd w(k), e(Z.cols());
    for (int i = 0; i < k; ++i) w(i) = std::sqrt(sigma2_um2) * normal(rng);
    for (Eigen::Index j = 0; j < Z.cols(); ++j) e(j) = normal(rng);
    w += Z * e;
    const double q = w.squaredNorm();
    sum += q, sum2 += q * q;
    rejected += FUpperTail(q / out.law.mean_um2, out.law.dof, 1e12) < 0.01;
    rejected_mean_only += FUpperTail((q - tr_a) / (k * sigma2_um2), k, 1e12) < 0.01;
  }
  out.mean_um2 = sum / draws;
  out.var_um4 = sum2 / draws - out.mean_um2 * out.mean_um2;
  out.rate = static_cast<double>(rejected) / draws;
  out.rate_mean_only = static_cast<double>(rejected_mean_only) / draws;
  return out;
}

// The diagnosis's case: the nuisance split fits every direction of the reference's variance above
// sigma^2, and orthonormal directions (a candidate's) cannot gather more along any one (Cauchy
// interlacing), so A's eigenvalues are at most sigma^2: here sigma^2 on 3 of the 4 components.
// And a stress case, eigenvalues up to 1.3 um^2 = 5 sigma^2 (a split at 5 sigma^2). Truth: 400 000
// draws each. The sample moments match the law's (sd of the mean 0.2 %, of the variance about
// 1 %); the law's test rejects within 0.5 % of its nominal 1 % (two moments matched, not the tail;
// the draws' binomial sd is 0.016 %; measured 1.00 % and 1.20 %), where the mean taken off rejects
// more than four times (measured 5.7 %) and more than five times (12.8 %) as often.
TEST(SatterthwaiteLaw, KeepsTheFalseAlarmRateWhereTheMeanAloneDoesNot) {
  constexpr double kSigma2 = 0.25;
  Eigen::MatrixXd at_threshold = Eigen::MatrixXd::Zero(4, 3);
  at_threshold.topRows(3) = 0.5 * Eigen::MatrixXd::Identity(3, 3);
  Eigen::MatrixXd stress(4, 3);
  stress << 1.0, 0.0, 0.0, 0.5, 0.5, 0.0, 0.0, 0.0, 0.3, 0.0, 0.2, 0.2;
  for (const auto& [Z, factor] : {std::pair{at_threshold, 4.0}, std::pair{stress, 5.0}}) {
    const Draws d = DrawSums(Z, kSigma2, 400000);
    EXPECT_NEAR(d.mean_um2, d.law.mean_um2, 0.01 * d.law.mean_um2);
    EXPECT_NEAR(d.var_um4, 2.0 * d.law.mean_um2 * d.law.mean_um2 / d.law.dof, 0.05 * d.var_um4);
    EXPECT_NEAR(d.rate, 0.01, 0.005);
    EXPECT_GT(d.rate_mean_only, factor * d.rate);
  }
}

}  // namespace
}  // namespace tpcal::pipeline::diagnosis_internal
