#include "fitting/leave_one_out.h"

#include <gtest/gtest.h>

#include <Eigen/QR>
#include <random>

#include "fitting/circle_fit.h"
#include "fitting/reference_data.h"

namespace tpcal::fitting {
namespace {

// Linear least squares (a quadratic in x): the closed form is exact, so it must match
// naive refits to rounding.
TEST(LeaveOneOut, MatchesRefitsExactlyForLinearLeastSquares) {
  std::mt19937_64 rng(71);
  std::normal_distribution<double> noise(0.0, 0.01);
  const int n = 40;
  Eigen::MatrixXd a(n, 3);
  Eigen::VectorXd y(n);
  for (int i = 0; i < n; ++i) {
    const double x = -2.0 + 4.0 * i / (n - 1);
    a.row(i) << 1.0, x, x * x;
    y[i] = 0.5 - 0.3 * x + 0.1 * x * x + noise(rng);
  }
  const Eigen::VectorXd theta = a.colPivHouseholderQr().solve(y);
  // Residual convention: model minus data, J = d r / d theta = A.
  const Eigen::VectorXd r = a * theta - y;
  const auto loo = ComputeLeaveOneOut(a, std::span<const double>(r.data(), n));
  ASSERT_TRUE(loo.ok()) << loo.status().ToString();
  EXPECT_NEAR(loo->leverage.sum(), 3.0, 1e-12);
  for (int i = 0; i < n; ++i) {
    Eigen::MatrixXd ai(n - 1, 3);
    Eigen::VectorXd yi(n - 1);
    for (int k = 0, m = 0; k < n; ++k) {
      if (k == i) continue;
      ai.row(m) = a.row(k);
      yi[m++] = y[k];
    }
    const Eigen::VectorXd ti = ai.colPivHouseholderQr().solve(yi);
    EXPECT_LT((loo->delta.row(i).transpose() - (ti - theta)).norm(), 1e-12) << "observation " << i;
    EXPECT_NEAR(loo->press_residuals[i], a.row(i).dot(ti) - y[i], 1e-12);
  }
}

// Nonlinear fit (FitCircle2 with keep_jacobian): first order in sigma/R = 1e-4, so the
// closed form agrees with refits to ~1e-4 of the delta's size; 2% is a safe bound.
TEST(LeaveOneOut, MatchesCircleRefitsToFirstOrder) {
  std::mt19937_64 rng(72);
  ReferenceOptions o;
  o.n_points = 30;
  o.arc_rad = 2.0;
  o.deviation_rms_mm = 0.002;
  const auto ref = MakeReferenceCircle2({{100.0, -50.0}, 20.0}, o, rng);
  ASSERT_TRUE(ref.ok());
  FitOptions opt;
  opt.keep_jacobian = true;
  const auto fit = FitCircle2(ref->points_mm, opt);
  ASSERT_TRUE(fit.ok());
  const auto loo = ComputeLeaveOneOut(fit->jacobian, fit->residuals_mm);
  ASSERT_TRUE(loo.ok()) << loo.status().ToString();
  for (std::size_t i = 0; i < ref->points_mm.size(); ++i) {
    std::vector<Eigen::Vector2d> p = ref->points_mm;
    p.erase(p.begin() + static_cast<std::ptrdiff_t>(i));
    const auto refit = FitCircle2(p);
    ASSERT_TRUE(refit.ok());
    Eigen::Vector3d naive;
    naive << refit->feature.center_mm - fit->feature.center_mm, refit->feature.radius_mm - fit->feature.radius_mm;
    const Eigen::Vector3d closed = loo->delta.row(static_cast<Eigen::Index>(i)).transpose();
    EXPECT_LT((closed - naive).norm(), 0.02 * naive.norm() + 1e-12) << "point " << i;
  }
  // Jackknife covariance agrees with sigma^2 (J^T J)^-1 for well-behaved data (within the
  // jackknife's own scatter at n = 30: 40%).
  const Eigen::MatrixXd jk = JackknifeCovariance(*loo);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(jk(k, k) / fit->covariance(k, k), 1.0, 0.4) << k;
}

TEST(LeaveOneOut, Errors) {
  const Eigen::MatrixXd j = Eigen::MatrixXd::Ones(3, 2);
  const std::vector<double> r3 = {1, 2, 3}, r2 = {1, 2};
  EXPECT_EQ(ComputeLeaveOneOut(j, r2).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(ComputeLeaveOneOut(Eigen::MatrixXd::Ones(2, 2), r2).status().code(), StatusCode::kTooFewPoints);
  EXPECT_EQ(ComputeLeaveOneOut(j, r3).status().code(), StatusCode::kDegenerate);  // equal columns
  // A single observation carries the second parameter: leverage 1.
  Eigen::MatrixXd k(4, 2);
  k << 1, 0, 1, 0, 1, 0, 1, 1;
  const std::vector<double> r4 = {0.1, -0.1, 0.0, 0.0};
  EXPECT_EQ(ComputeLeaveOneOut(k, r4).status().code(), StatusCode::kNotIdentifiable);
}

}  // namespace
}  // namespace tpcal::fitting
