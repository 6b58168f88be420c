#include "fitting/reference_data.h"

#include <gtest/gtest.h>

#include <random>

namespace tpcal::fitting {
namespace {

// The certificate itself: deviations orthogonal to the Jacobian, RMS as asked.
TEST(ReferenceData, NullSpaceDeviationsAreOrthogonalToJ) {
  std::mt19937_64 rng(81);
  Eigen::MatrixXd j = Eigen::MatrixXd::Random(500, 6);
  j.col(5) = j.col(0) + j.col(1);  // rank-deficient columns are fine
  const Eigen::VectorXd e = NullSpaceDeviations(j, 0.002, rng);
  EXPECT_NEAR(std::sqrt(e.squaredNorm() / 500.0), 0.002, 1e-15);
  EXPECT_LT((j.transpose() * e).cwiseAbs().maxCoeff(), 1e-14 * j.norm() * e.norm());
  // As many rows as the rank: no null space, exact points.
  EXPECT_EQ(NullSpaceDeviations(Eigen::MatrixXd::Random(4, 4), 0.01, rng).norm(), 0.0);
}

TEST(ReferenceData, PointsLieAtTheCertifiedDistances) {
  std::mt19937_64 rng(82);
  ReferenceOptions o;
  o.n_points = 200;
  o.deviation_rms_mm = 0.005;
  o.arc_rad = 1.0;
  o.length_mm = 20.0;
  const Cylinder cyl = *MakeCylinder({1000, 0, 0}, {0, 1, 1}, 30.0);
  const auto c = MakeReferenceCylinder(cyl, o, rng);
  ASSERT_TRUE(c.ok());
  for (std::size_t i = 0; i < o.n_points; ++i) EXPECT_NEAR(Distance(cyl, c->points_mm[i]), c->residuals_mm[i], 1e-12);
  const Cone cone = *MakeCone({0, 1000, 0}, {1, 0, 0}, 0.4, 25.0);
  const auto k = MakeReferenceCone(cone, o, rng);
  ASSERT_TRUE(k.ok());
  for (std::size_t i = 0; i < o.n_points; ++i) EXPECT_NEAR(Distance(cone, k->points_mm[i]), k->residuals_mm[i], 1e-12);
  const Circle3 circle = *MakeCircle3({0, 0, 1000}, {1, 2, 3}, 40.0);
  const auto ci = MakeReferenceCircle3(circle, o, rng);
  ASSERT_TRUE(ci.ok());
  double axial_rms = 0.0;
  for (std::size_t i = 0; i < o.n_points; ++i) {
    const Eigen::Vector3d d = ci->points_mm[i] - circle.center_mm;
    const double h = circle.axis.dot(d);
    EXPECT_NEAR((d - h * circle.axis).norm() - 40.0, ci->residuals_mm[i], 1e-12);
    axial_rms += h * h;
  }
  EXPECT_NEAR(std::sqrt(axial_rms / 200.0), 0.005, 1e-12);
  const auto line = MakeReferenceLine3(*MakeLine3({5, 5, 5}, {1, 0, 0}), o, rng);
  ASSERT_TRUE(line.ok());
  double rms = 0.0;
  for (double r : line->residuals_mm) rms += r * r;
  EXPECT_NEAR(std::sqrt(rms / 200.0), 0.005, 1e-12);  // distance RMS as asked
}

TEST(ReferenceData, RejectsBadOptions) {
  std::mt19937_64 rng(83);
  ReferenceOptions o;
  o.n_points = 3;
  EXPECT_EQ(MakeReferenceSphere({{0, 0, 0}, 1.0}, o, rng).status().code(), StatusCode::kTooFewPoints);
  o.n_points = 10;
  o.arc_rad = 0.0;
  EXPECT_EQ(MakeReferenceCircle2({{0, 0}, 1.0}, o, rng).status().code(), StatusCode::kInvalidArgument);
  o.arc_rad = 1.0;
  o.length_mm = 10.0;
  // Apex inside the band: radius 1 at the centre, 45 deg, half length 5.
  EXPECT_EQ(MakeReferenceCone(*MakeCone({0, 0, 0}, {0, 0, 1}, 0.785, 1.0), o, rng).status().code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace tpcal::fitting
