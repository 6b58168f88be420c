#include "fitting/line_fit.h"

#include <gtest/gtest.h>

#include <random>
#include <sstream>

#include "fitting/reference_data.h"
#include "fitting/testing/fit_test_util.h"

namespace tpcal::fitting {
namespace {

using testing::kPosTol_mm;
using testing::LineAngle;

Eigen::Vector3d RandomUnitLine(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Eigen::Vector3d{g(rng), g(rng), g(rng)}.normalized();
}

Eigen::Vector3d Lift(const Eigen::Vector2d& p) { return {p.x(), p.y(), 0.0}; }

// Lengths 1 to 500 mm, 1000 mm from the origin, 2 to 10^5 points, deviations 0 to 10 um
// (at most 1% of the length, where the certificate holds).
TEST(FitLine2, CertifiedReferenceData) {
  std::mt19937_64 rng(20240604);
  testing::WorstCase worst("line2");
  for (double length_mm : {1.0, 10.0, 100.0, 500.0}) {
    for (std::size_t n : {2u, 3u, 10u, 1000u, 100000u}) {
      if (n == 100000u && length_mm < 500.0) continue;  // large sets: a few
      for (double dev_mm : {0.0, 0.001, 0.01}) {
        if (dev_mm > 0.01 * length_mm) continue;
        ReferenceOptions o;
        o.n_points = n;
        o.length_mm = length_mm;
        o.deviation_rms_mm = dev_mm;
        const Eigen::Vector3d dir = RandomUnitLine(rng), pos = 1000.0 * RandomUnitLine(rng);
        const Line2 truth{pos.head<2>(), dir.head<2>().normalized()};
        const auto ref = MakeReferenceLine2(truth, o, rng);
        ASSERT_TRUE(ref.ok()) << ref.status().ToString();
        std::ostringstream label;
        label << "L " << length_mm << " n " << n << " dev " << dev_mm;
        const auto fit = FitLine2(ref->points_mm);
        ASSERT_TRUE(fit.ok()) << label.str() << ": " << fit.status().ToString();
        const double sign = fit->feature.direction.dot(truth.direction) > 0.0 ? 1.0 : -1.0;
        double res_err = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
          res_err = std::max(res_err, std::abs(sign * fit->residuals_mm[i] - ref->residuals_mm[i]));
        }
        EXPECT_LT(res_err, kPosTol_mm) << label.str();
        worst.Add(label.str(), Distance(truth, fit->feature.point_mm),
                  LineAngle(Lift(fit->feature.direction), Lift(truth.direction)), res_err);
      }
    }
  }
  worst.PrintAndCheck();  // "size": residual error
}

TEST(FitLine3, CertifiedReferenceData) {
  std::mt19937_64 rng(20240605);
  testing::WorstCase worst("line3");
  for (double length_mm : {1.0, 10.0, 100.0, 500.0}) {
    for (std::size_t n : {2u, 3u, 10u, 1000u, 100000u}) {
      if (n == 100000u && length_mm < 500.0) continue;
      for (double dev_mm : {0.0, 0.001, 0.01}) {
        if (dev_mm > 0.01 * length_mm) continue;
        ReferenceOptions o;
        o.n_points = n;
        o.length_mm = length_mm;
        o.deviation_rms_mm = dev_mm;
        const Eigen::Vector3d point = 1000.0 * RandomUnitLine(rng);  // drawn before the direction under every compiler
        const Eigen::Vector3d direction = RandomUnitLine(rng);
        const Line3 truth = *MakeLine3(point, direction);
        const auto ref = MakeReferenceLine3(truth, o, rng);
        ASSERT_TRUE(ref.ok()) << ref.status().ToString();
        std::ostringstream label;
        label << "L " << length_mm << " n " << n << " dev " << dev_mm;
        const auto fit = FitLine3(ref->points_mm);
        ASSERT_TRUE(fit.ok()) << label.str() << ": " << fit.status().ToString();
        double res_err = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
          res_err = std::max(res_err, std::abs(fit->residuals_mm[i] - ref->residuals_mm[i]));
        }
        EXPECT_LT(res_err, kPosTol_mm) << label.str();
        worst.Add(label.str(), Distance(truth, fit->feature.point_mm), LineAngle(fit->feature.direction, truth.direction),
                  res_err);
      }
    }
  }
  worst.PrintAndCheck();
}

TEST(FitLine3, RigidMotionAndOrder) {
  std::mt19937_64 rng(31);
  ReferenceOptions o;
  o.n_points = 100;
  o.length_mm = 120.0;
  o.deviation_rms_mm = 0.004;
  const auto ref = MakeReferenceLine3(*MakeLine3({1, 2, 3}, {1, 1, 0}), o, rng);
  const auto fit = FitLine3(ref->points_mm);
  ASSERT_TRUE(fit.ok());
  for (int k = 0; k < 4; ++k) {
    const Rigid3 t = testing::RandomRigid(rng, 1000.0);
    const auto moved = FitLine3(testing::Apply(t, ref->points_mm));
    ASSERT_TRUE(moved.ok());
    EXPECT_LT((moved->feature.point_mm - t * fit->feature.point_mm).norm(), 1e-10);
    // The sign rule (last - first point) moves with the points.
    EXPECT_LT(testing::DirectionAngle(moved->feature.direction, t.linear() * fit->feature.direction), 1e-12);
    EXPECT_NEAR(moved->stats.rms_mm, fit->stats.rms_mm, 1e-12);
  }
  const auto shuffled = FitLine3(testing::Shuffled(ref->points_mm, rng));
  ASSERT_TRUE(shuffled.ok());
  EXPECT_LT((shuffled->feature.point_mm - fit->feature.point_mm).norm(), 1e-12);
  EXPECT_LT(LineAngle(shuffled->feature.direction, fit->feature.direction), 1e-13);
}

TEST(FitLine2, RigidMotionAndSign) {
  std::mt19937_64 rng(32);
  ReferenceOptions o;
  o.n_points = 50;
  o.length_mm = 60.0;
  o.deviation_rms_mm = 0.003;
  const auto ref = MakeReferenceLine2({{5, 5}, {0.6, 0.8}}, o, rng);
  const auto fit = FitLine2(ref->points_mm);
  ASSERT_TRUE(fit.ok());
  EXPECT_GT(fit->feature.direction.dot(ref->points_mm.back() - ref->points_mm.front()), 0.0);
  const double angle = 2.0;
  const Eigen::Vector2d t(-700.0, 900.0);
  const auto moved = FitLine2(testing::Apply2(angle, t, ref->points_mm));
  ASSERT_TRUE(moved.ok());
  EXPECT_LT((moved->feature.point_mm - (Eigen::Rotation2Dd(angle) * fit->feature.point_mm + t)).norm(), 1e-10);
  EXPECT_LT((moved->feature.direction - Eigen::Rotation2Dd(angle) * fit->feature.direction).norm(), 1e-12);
  for (std::size_t i = 0; i < ref->points_mm.size(); ++i) ASSERT_NEAR(moved->residuals_mm[i], fit->residuals_mm[i], 1e-11);
  // Covariance: offset variance sigma^2 / n.
  EXPECT_NEAR(fit->covariance(0, 0), fit->stats.sigma_mm * fit->stats.sigma_mm / 50.0, 1e-18);
}

TEST(FitLine, DegenerateInputIsAnError) {
  EXPECT_EQ(FitLine2(std::vector<Eigen::Vector2d>{{1, 1}}).status().code(), StatusCode::kTooFewPoints);
  EXPECT_EQ(FitLine3(std::vector<Eigen::Vector3d>(4, Eigen::Vector3d(1, 2, 3))).status().code(), StatusCode::kDegenerate);
  // A regular hexagon has an isotropic scatter: no LS line direction.
  std::vector<Eigen::Vector2d> hexagon;
  for (int k = 0; k < 6; ++k) hexagon.push_back(Eigen::Vector2d(std::cos(k * kPi / 3), std::sin(k * kPi / 3)));
  const auto iso = FitLine2(hexagon);
  EXPECT_EQ(iso.status().code(), StatusCode::kDegenerate) << iso.status().ToString();
  std::vector<Eigen::Vector3d> hex3;
  for (const auto& p : hexagon) hex3.push_back(Eigen::Vector3d(p.x(), p.y(), 0.0));
  EXPECT_EQ(FitLine3(hex3).status().code(), StatusCode::kDegenerate);
  EXPECT_EQ(FitLine3(std::vector<Eigen::Vector3d>{{0, 0, 0}, {1, 0, NAN}}).status().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace tpcal::fitting
