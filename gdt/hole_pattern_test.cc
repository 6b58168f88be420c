#include "gdt/hole_pattern.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/units.h"

namespace tpcal::gdt {
namespace {

constexpr double kHoleAngleTol_rad = 1e-14;  // atan2 of exact-ish coordinates near 140 mm
constexpr double kHoleTol_mm = 1e-12;

TEST(WrapAngle, MapsIntoHalfOpenInterval) {
  EXPECT_NEAR(WrapAngle(3 * kPi), kPi, 1e-15);
  EXPECT_NEAR(WrapAngle(-kPi), kPi, 1e-15);
  EXPECT_NEAR(WrapAngle(2 * kPi + 0.1), 0.1, 1e-15);
  EXPECT_NEAR(WrapAngle(-0.1), -0.1, 1e-15);
}

TEST(EvaluateHolePattern, AngleErrorsAreCounterClockwiseAboutThePitchCentre) {
  const fitting::Circle2 pitch{{0.010, -0.017}, 140.0};
  const double eps = 30e-6;  // hole 5 rotated counter-clockwise by 30 urad
  std::vector<Eigen::Vector2d> centres;
  std::vector<double> nominal;
  for (int k = 0; k < 16; ++k) {
    const double a = DegToRad(22.5 * k) + (k == 4 ? eps : 0.0);
    centres.push_back(pitch.center_mm + pitch.radius_mm * Eigen::Vector2d(std::cos(a), std::sin(a)));
    nominal.push_back(DegToRad(22.5 * k));
  }
  centres[7] += 0.002 * (centres[7] - pitch.center_mm).normalized();  // hole 8: 2 um outward
  auto r = EvaluateHolePattern(pitch, centres, nominal);
  ASSERT_TRUE(r.ok());
  for (int k = 0; k < 16; ++k) {
    EXPECT_NEAR(r->holes[k].angle_error_rad, k == 4 ? eps : 0.0, kHoleAngleTol_rad) << "hole " << k + 1;
    EXPECT_NEAR(r->holes[k].radial_error_mm, k == 7 ? 0.002 : 0.0, kHoleTol_mm) << "hole " << k + 1;
  }
  EXPECT_NEAR(r->mean_angle_error_rad, eps / 16, 1e-12);
}

TEST(EvaluateHolePattern, HoleNearMinusPiWrapsSmall) {
  const fitting::Circle2 pitch{{0, 0}, 1.0};
  const std::vector<Eigen::Vector2d> c = {{std::cos(kPi - 1e-6), std::sin(kPi - 1e-6)}};
  const std::vector<double> nominal = {-kPi};
  auto r = EvaluateHolePattern(pitch, c, nominal);
  EXPECT_NEAR(r->holes[0].angle_error_rad, -1e-6, 1e-12);
}

TEST(EvaluateHolePattern, SizeMismatchIsAnError) {
  const std::vector<Eigen::Vector2d> c = {{1, 0}, {0, 1}};
  const std::vector<double> nominal = {0.0};
  auto r = EvaluateHolePattern({{0, 0}, 1.0}, c, nominal);
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace tpcal::gdt
