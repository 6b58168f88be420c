#include "core/tall_qr.h"

#include <gtest/gtest.h>

#include <random>

namespace tpcal {
namespace {

Eigen::MatrixXd Random(Eigen::Index n, Eigen::Index p, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd A(n, p);
  for (Eigen::Index j = 0; j < p; ++j)
    for (Eigen::Index i = 0; i < n; ++i) A(i, j) = g(rng) + (j > 0 ? 0.9 * A(i, j - 1) : 0.0);  // correlated columns
  return A;
}

// Truth: A = Q R with Q^T Q = I and R upper triangular, for one block, several blocks with a
// remainder, and a wide matrix. Tolerance 1e-12 relative: Householder QR is backward stable
// (error ~ p n^0.5 eps ||A|| at these sizes, below 1e-12).
TEST(TallQr, FactorsInBlocksLikeOneHouseholderQr) {
  for (const auto& [n, p] : {std::pair<Eigen::Index, Eigen::Index>{300, 5}, {3 * kTallQrBlockRows + 123, 7},
                             {2 * kTallQrBlockRows + 1, 30}, {4, 9}}) {
    const Eigen::MatrixXd A = Random(n, p, 7 + static_cast<std::uint64_t>(n));
    Eigen::MatrixXd W = A;
    const TallQr qr(&W);
    const Eigen::Index m = std::min(n, p);
    const Eigen::MatrixXd R = qr.R();
    ASSERT_EQ(R.rows(), m);
    ASSERT_EQ(R.cols(), p);
    EXPECT_EQ((R - Eigen::MatrixXd(R.triangularView<Eigen::Upper>())).norm(), 0.0);
    const Eigen::MatrixXd Q = qr.ApplyQ(Eigen::MatrixXd::Identity(m, m));
    ASSERT_EQ(Q.rows(), n);
    EXPECT_LT((Q.transpose() * Q - Eigen::MatrixXd::Identity(m, m)).norm(), 1e-12) << n << " x " << p;
    EXPECT_LT((Q * R - A).norm(), 1e-12 * A.norm()) << n << " x " << p;
    // The Gram matrix is that of A (R equals the plain factor up to row signs).
    EXPECT_LT((R.transpose() * R - A.transpose() * A).norm(), 1e-12 * A.squaredNorm());
  }
}

}  // namespace
}  // namespace tpcal
