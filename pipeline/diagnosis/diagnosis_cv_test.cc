#include "pipeline/diagnosis/diagnosis_cv.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <Eigen/QR>
#include <Eigen/SVD>
#include <cmath>
#include <optional>
#include <random>

namespace tpcal::pipeline {
namespace {

// Exact linear algebra on a well-conditioned design: Woodbury and refit agree to rounding.
constexpr double kRelTol = 1e-9;
constexpr double kHoldoutTol = 1e-6;  // DiagnosisOptions::holdout_tolerance default

struct Design {
  Eigen::MatrixXd X;
  Eigen::VectorXd y;
  std::vector<int> group;
  int n_groups = 0;
};

// Groups of 3 to 9 points, p random columns plus a constant column, y random.
Design RandomDesign(std::mt19937_64& rng, int n_groups, int p) {
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_int_distribution<int> size(3, 9);
  Design d;
  d.n_groups = n_groups;
  for (int g = 0; g < n_groups; ++g)
    for (int k = size(rng); k > 0; --k) d.group.push_back(g);
  const auto n = static_cast<Eigen::Index>(d.group.size());
  d.X.resize(n, p + 1);
  d.y.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    d.X(i, 0) = 1.0;
    for (int j = 1; j <= p; ++j) d.X(i, j) = normal(rng);
    d.y(i) = normal(rng);
  }
  return d;
}

Eigen::MatrixXd OrthonormalBasis(const Eigen::MatrixXd& X) {
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(X, Eigen::ComputeThinU);
  int rank = 0;
  for (Eigen::Index k = 0; k < svd.singularValues().size(); ++k)
    if (svd.singularValues()(k) > 1e-10 * svd.singularValues()(0)) ++rank;
  return svd.matrixU().leftCols(rank);
}

// Brute force: refit on the other groups' rows, predict group g. nullopt when the design
// without g is rank-deficient.
std::optional<Eigen::VectorXd> RefitWithout(const Design& d, int g) {
  std::vector<Eigen::Index> keep, held;
  for (std::size_t i = 0; i < d.group.size(); ++i) (d.group[i] == g ? held : keep).push_back(static_cast<Eigen::Index>(i));
  Eigen::MatrixXd Xk(static_cast<Eigen::Index>(keep.size()), d.X.cols());
  Eigen::VectorXd yk(Xk.rows());
  for (std::size_t k = 0; k < keep.size(); ++k) {
    Xk.row(static_cast<Eigen::Index>(k)) = d.X.row(keep[k]);
    yk(static_cast<Eigen::Index>(k)) = d.y(keep[k]);
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Xk);
  qr.setThreshold(1e-10);
  if (qr.rank() < d.X.cols()) return std::nullopt;
  const Eigen::VectorXd beta = qr.solve(yk);
  Eigen::VectorXd e(static_cast<Eigen::Index>(held.size()));
  for (std::size_t k = 0; k < held.size(); ++k) e(static_cast<Eigen::Index>(k)) = d.y(held[k]) - d.X.row(held[k]).dot(beta);
  return e;
}

void ExpectMatchesRefits(const Design& d, const GroupCvResult& cv, std::vector<bool>* seen_unholdable) {
  double ss = 0.0;
  int counted = 0;
  for (int g = 0; g < d.n_groups; ++g) {
    const auto brute = RefitWithout(d, g);
    EXPECT_EQ(cv.holdable[static_cast<std::size_t>(g)], brute.has_value()) << "group " << g;
    if (!brute) {
      seen_unholdable->push_back(true);
      EXPECT_LT(cv.min_information[static_cast<std::size_t>(g)], 1e-12);
      continue;
    }
    Eigen::Index k = 0;
    for (std::size_t i = 0; i < d.group.size(); ++i) {
      if (d.group[i] != g) continue;
      const double want = (*brute)(k++);
      const double got = cv.heldout_residual(static_cast<Eigen::Index>(i));
      ASSERT_FALSE(std::isnan(got));
      EXPECT_NEAR(got, want, kRelTol * std::max(1.0, std::abs(want))) << "group " << g << " point " << i;
      ss += want * want;
      ++counted;
    }
  }
  EXPECT_NEAR(cv.Rms(), std::sqrt(ss / counted), kRelTol * std::sqrt(ss / counted));
}

Eigen::VectorXd Residual(const Eigen::MatrixXd& Q, const Eigen::VectorXd& y) { return y - Q * (Q.transpose() * y); }

TEST(DiagnosisCv, GroupResidualsEqualBruteForceRefits) {
  std::mt19937_64 rng(20261125);
  for (int trial = 0; trial < 5; ++trial) {
    const Design d = RandomDesign(rng, 7, 4);
    const Eigen::MatrixXd Q = OrthonormalBasis(d.X);
    const GroupCrossValidation cv(Q, d.group, d.n_groups, kHoldoutTol);
    const GroupCvResult r = cv.Evaluate(Residual(Q, d.y));
    std::vector<bool> unholdable;
    ExpectMatchesRefits(d, r, &unholdable);
    EXPECT_TRUE(unholdable.empty());
  }
}

// A column that is non-zero only on group 2: its coefficient is fixed by group 2's points
// alone, so group 2 cannot be held out; every other group still matches its refit.
TEST(DiagnosisCv, GroupThatAloneDeterminesADirectionIsNotHoldable) {
  std::mt19937_64 rng(7);
  Design d = RandomDesign(rng, 6, 3);
  d.X.conservativeResize(Eigen::NoChange, d.X.cols() + 1);
  for (std::size_t i = 0; i < d.group.size(); ++i)
    d.X(static_cast<Eigen::Index>(i), d.X.cols() - 1) = d.group[i] == 2 ? 1.0 + 0.1 * static_cast<double>(i % 3) : 0.0;
  const Eigen::MatrixXd Q = OrthonormalBasis(d.X);
  ASSERT_EQ(Q.cols(), d.X.cols());
  const GroupCrossValidation cv(Q, d.group, d.n_groups, kHoldoutTol);
  const GroupCvResult r = cv.Evaluate(Residual(Q, d.y));
  std::vector<bool> unholdable;
  ExpectMatchesRefits(d, r, &unholdable);
  EXPECT_EQ(unholdable.size(), 1u);
  EXPECT_FALSE(r.holdable[2]);
  EXPECT_EQ(r.ss_by_group[2], 0.0);
  for (std::size_t i = 0; i < d.group.size(); ++i) {
    if (d.group[i] == 2) {
      EXPECT_EQ(r.heldout_residual(static_cast<Eigen::Index>(i)), 0.0);
    }
  }
}

// Two blocks (base and a candidate projected on its complement) give the single-block result.
TEST(DiagnosisCv, TwoBlocksEqualTheJointBasis) {
  std::mt19937_64 rng(99);
  const Design d = RandomDesign(rng, 8, 5);
  const Eigen::MatrixXd Q = OrthonormalBasis(d.X);
  const Eigen::MatrixXd Q0 = Q.leftCols(3), Q1 = Q.rightCols(Q.cols() - 3);
  const Eigen::VectorXd e = Residual(Q, d.y);
  const GroupCvResult joint = GroupCrossValidation(Q, d.group, d.n_groups, kHoldoutTol).Evaluate(e);
  const GroupCvResult blocks = GroupCrossValidation(Q0, d.group, d.n_groups, kHoldoutTol).Evaluate(Q1, e);
  ASSERT_EQ(joint.holdable, blocks.holdable);
  for (Eigen::Index i = 0; i < e.size(); ++i)
    EXPECT_NEAR(blocks.heldout_residual(i), joint.heldout_residual(i), kRelTol * std::max(1.0, std::abs(joint.heldout_residual(i))));
  std::vector<bool> unholdable;
  ExpectMatchesRefits(d, blocks, &unholdable);
}

// Interleaved groups (points of a group not consecutive: rows gathered) against the brute-force
// refits, as the consecutive case (rows read in place) is by the tests above; the two-block
// form too.
TEST(DiagnosisCv, InterleavedGroupsEqualBruteForceRefits) {
  std::mt19937_64 rng(11);
  Design d = RandomDesign(rng, 6, 3);
  std::shuffle(d.group.begin(), d.group.end(), rng);
  const Eigen::MatrixXd Q = OrthonormalBasis(d.X);
  const GroupCvResult r = GroupCrossValidation(Q, d.group, d.n_groups, kHoldoutTol).Evaluate(Residual(Q, d.y));
  std::vector<bool> unholdable;
  ExpectMatchesRefits(d, r, &unholdable);
  const GroupCvResult blocks =
      GroupCrossValidation(Q.leftCols(2), d.group, d.n_groups, kHoldoutTol).Evaluate(Q.rightCols(Q.cols() - 2), Residual(Q, d.y));
  ExpectMatchesRefits(d, blocks, &unholdable);
}

// Single-point groups: the group residual is the PRESS residual e_i / (1 - h_ii).
TEST(DiagnosisCv, SinglePointGroupsArePress) {
  std::mt19937_64 rng(3);
  Design d = RandomDesign(rng, 12, 2);
  for (std::size_t i = 0; i < d.group.size(); ++i) d.group[i] = static_cast<int>(i);
  d.n_groups = static_cast<int>(d.group.size());
  const Eigen::MatrixXd Q = OrthonormalBasis(d.X);
  const Eigen::VectorXd e = Residual(Q, d.y);
  const GroupCvResult r = GroupCrossValidation(Q, d.group, d.n_groups, kHoldoutTol).Evaluate(e);
  for (Eigen::Index i = 0; i < e.size(); ++i) {
    const double press = e(i) / (1.0 - Q.row(i).squaredNorm());
    EXPECT_NEAR(r.heldout_residual(i), press, kRelTol * std::max(1.0, std::abs(press)));
  }
}

}  // namespace
}  // namespace tpcal::pipeline
