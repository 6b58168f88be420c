#include "pipeline/diagnosis/diagnosis_least_squares.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

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

// A sum of squares of k = 4 components: noise of sigma^2 = 0.25 um^2 and a correlated part
// Z Z^T whose largest eigenvalue is 1.3 um^2 (5 sigma^2; a reference's leftover variance below
// its threshold is at most sigma^2 per direction, more where directions pile up on a few
// components). Truth: 400 000 draws (seed 7). The test Q / mean on (d, infinity) must reject at
// its nominal 1 % within 0.5 % (Satterthwaite matches two moments, not the tail; the draws'
// binomial sd is 0.016 %; measured 1.20 %); the mean taken off instead ((Q - tr A) / (k sigma^2)
// on k degrees of freedom: the reduction's spread ignored) rejects more than five times as often
// (measured 12.8 %).
TEST(SatterthwaiteLaw, KeepsTheFalseAlarmRateWhereTheMeanAloneDoesNot) {
  constexpr int kK = 4;
  constexpr double kSigma2 = 0.25;
  Eigen::MatrixXd Z(kK, 3);
  Z << 1.0, 0.0, 0.0, 0.5, 0.5, 0.0, 0.0, 0.0, 0.3, 0.0, 0.2, 0.2;
  const ChiSquareLaw law = SatterthwaiteLaw(kK, kSigma2, Z);
  const double tr_a = Z.squaredNorm();
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  constexpr int kDraws = 400000;
  int rejected = 0, rejected_mean_only = 0;
  double sum = 0.0, sum2 = 0.0;
  for (int draw = 0; draw < kDraws; ++draw) {
    Eigen::VectorXd w(kK);
    for (int i = 0; i < kK; ++i) w(i) = std::sqrt(kSigma2) * normal(rng);
    Eigen::Vector3d e;
    for (int j = 0; j < 3; ++j) e(j) = normal(rng);
    w += Z * e;
    const double q = w.squaredNorm();
    sum += q, sum2 += q * q;
    rejected += FUpperTail(q / law.mean_um2, law.dof, 1e12) < 0.01;
    rejected_mean_only += FUpperTail((q - tr_a) / (kK * kSigma2), kK, 1e12) < 0.01;
  }
  const double mean = sum / kDraws, var = sum2 / kDraws - mean * mean;
  EXPECT_NEAR(mean, law.mean_um2, 0.01 * law.mean_um2);                          // sd of the mean: 0.2 %
  EXPECT_NEAR(var, 2.0 * law.mean_um2 * law.mean_um2 / law.dof, 0.05 * var);    // sd of the variance: ~1 %
  const double rate = static_cast<double>(rejected) / kDraws;
  const double rate_mean_only = static_cast<double>(rejected_mean_only) / kDraws;
  EXPECT_NEAR(rate, 0.01, 0.005);
  EXPECT_GT(rate_mean_only, 5.0 * rate);
}

}  // namespace
}  // namespace tpcal::pipeline::diagnosis_internal
