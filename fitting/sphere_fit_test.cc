#include "fitting/sphere_fit.h"

#include <gtest/gtest.h>

#include <random>
#include <sstream>

#include "fitting/reference_data.h"
#include "fitting/testing/fit_test_util.h"

namespace tpcal::fitting {
namespace {

using testing::kPosTol_mm;
using testing::kSizeTol_mm;

Eigen::Vector3d RandomUnitSphere(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Eigen::Vector3d{g(rng), g(rng), g(rng)}.normalized();
}

// Radii 1 to 500 mm, caps from the whole sphere down to 20 deg half angle, centres 1000 mm
// from the origin, 4 to 10^5 points, deviations 0 to 10 um (certifiable: at most 1% of
// R x cap^2).
TEST(FitSphere, CertifiedReferenceData) {
  std::mt19937_64 rng(20240606);
  testing::WorstCase worst("sphere");
  for (double radius_mm : {1.0, 10.0, 100.0, 500.0}) {
    for (double cap_deg : {180.0, 90.0, 45.0, 20.0}) {
      for (std::size_t n : {4u, 7u, 10u, 100u, 1000u, 1001u}) {
        for (double dev_mm : {0.0, 0.001, 0.01}) {
          const double cap = DegToRad(cap_deg);
          if (dev_mm > std::min(0.01, 0.01 * radius_mm * cap * cap)) continue;
          ReferenceOptions o;
          o.n_points = n;
          o.arc_rad = cap;
          o.cap_axis = RandomUnitSphere(rng);
          o.deviation_rms_mm = dev_mm;
          const auto ref = MakeReferenceSphere({1000.0 * RandomUnitSphere(rng), radius_mm}, o, rng);
          ASSERT_TRUE(ref.ok()) << ref.status().ToString();
          std::ostringstream label;
          label << "R " << radius_mm << " cap " << cap_deg << " n " << n << " dev " << dev_mm;
          const auto fit = FitSphere(ref->points_mm);
          ASSERT_TRUE(fit.ok()) << label.str() << ": " << fit.status().ToString();
          double res_err = 0.0;
          for (std::size_t i = 0; i < n; ++i) {
            res_err = std::max(res_err, std::abs(fit->residuals_mm[i] - ref->residuals_mm[i]));
          }
          EXPECT_LT(res_err, kSizeTol_mm) << label.str();
          worst.Add(label.str(), (fit->feature.center_mm - ref->truth.center_mm).norm(), 0.0,
                    std::abs(fit->feature.radius_mm - ref->truth.radius_mm));
        }
      }
    }
  }
  for (double cap_deg : {180.0, 30.0}) {
    ReferenceOptions o;
    o.n_points = 100000;
    o.arc_rad = DegToRad(cap_deg);
    o.deviation_rms_mm = 0.002;
    const auto ref = MakeReferenceSphere({1000.0 * RandomUnitSphere(rng), 12.5}, o, rng);
    ASSERT_TRUE(ref.ok());
    const auto fit = FitSphere(ref->points_mm);
    ASSERT_TRUE(fit.ok()) << fit.status().ToString();
    worst.Add("R 12.5 n 1e5 cap " + std::to_string(cap_deg), (fit->feature.center_mm - ref->truth.center_mm).norm(),
              0.0, std::abs(fit->feature.radius_mm - ref->truth.radius_mm));
  }
  worst.PrintAndCheck();
}

TEST(FitSphere, RigidMotionAndOrder) {
  std::mt19937_64 rng(41);
  ReferenceOptions o;
  o.n_points = 80;
  o.arc_rad = DegToRad(60.0);
  o.deviation_rms_mm = 0.002;
  const auto ref = MakeReferenceSphere({{1, 2, 3}, 10.0}, o, rng);
  const auto fit = FitSphere(ref->points_mm);
  ASSERT_TRUE(fit.ok());
  for (int k = 0; k < 4; ++k) {
    const Rigid3 t = testing::RandomRigid(rng, 1000.0);
    const auto moved = FitSphere(testing::Apply(t, ref->points_mm));
    ASSERT_TRUE(moved.ok());
    EXPECT_LT((moved->feature.center_mm - t * fit->feature.center_mm).norm(), 1e-9);
    EXPECT_NEAR(moved->feature.radius_mm, fit->feature.radius_mm, 1e-9);
    for (std::size_t i = 0; i < ref->points_mm.size(); ++i) ASSERT_NEAR(moved->residuals_mm[i], fit->residuals_mm[i], 1e-10);
    EXPECT_NEAR(moved->covariance(3, 3), fit->covariance(3, 3), 1e-6 * fit->covariance(3, 3));
  }
  const auto shuffled = FitSphere(testing::Shuffled(ref->points_mm, rng));
  ASSERT_TRUE(shuffled.ok());
  EXPECT_LT((shuffled->feature.center_mm - fit->feature.center_mm).norm(), 1e-10);
}

TEST(FitSphere, DegenerateInputIsAnError) {
  EXPECT_EQ(FitSphere(std::vector<Eigen::Vector3d>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}).status().code(),
            StatusCode::kTooFewPoints);
  // Points on one circle (coplanar): a family of spheres fits them.
  std::vector<Eigen::Vector3d> ring;
  for (int k = 0; k < 12; ++k) ring.push_back(Eigen::Vector3d(1000 + 5 * std::cos(k * 0.5), 5 * std::sin(k * 0.5), 7.0));
  const auto coplanar = FitSphere(ring);
  ASSERT_EQ(coplanar.status().code(), StatusCode::kDegenerate);
  EXPECT_NE(coplanar.status().message().find("coplanar"), std::string::npos) << coplanar.status().message();
  std::vector<Eigen::Vector3d> same(6, Eigen::Vector3d(3, 3, 3));
  EXPECT_EQ(FitSphere(same).status().code(), StatusCode::kDegenerate);
}

TEST(FitSphere, FourPointsGiveTheCircumsphere) {
  // Regular tetrahedron vertices on the unit sphere, shifted far away.
  const Eigen::Vector3d c(-1000.0, 500.0, 1000.0);
  const double s = 1.0 / std::sqrt(3.0);
  const std::vector<Eigen::Vector3d> p = {c + s * Eigen::Vector3d(1, 1, 1), c + s * Eigen::Vector3d(1, -1, -1),
                                          c + s * Eigen::Vector3d(-1, 1, -1), c + s * Eigen::Vector3d(-1, -1, 1)};
  const auto fit = FitSphere(p);
  ASSERT_TRUE(fit.ok()) << fit.status().ToString();
  EXPECT_LT((fit->feature.center_mm - c).norm(), 1e-12);
  EXPECT_NEAR(fit->feature.radius_mm, 1.0, 1e-12);
}

}  // namespace
}  // namespace tpcal::fitting
