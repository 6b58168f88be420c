#include "gdt/form.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/units.h"

namespace tpcal::gdt {
namespace {

constexpr double kFormTol_mm = 1e-12;  // closed-form arithmetic on coordinates below 200 mm

TEST(CircularityProfile, RecoversAKnownRadialProfileSortedByTheta) {
  const fitting::Circle2 c{{3.0, -4.0}, 160.0};
  auto dr = [](double t) { return 0.0015 * std::cos(3 * t) + 0.0008 * std::sin(2 * t); };
  std::vector<Eigen::Vector2d> pts;
  // Points listed starting at 180 deg, so sorting by theta is visible.
  for (int k = 0; k < 16; ++k) {
    const double t = kPi + 2 * kPi * k / 16;
    pts.push_back(c.center_mm + (c.radius_mm + dr(t)) * Eigen::Vector2d(std::cos(t), std::sin(t)));
  }
  const auto profile = CircularityProfile(pts, c);
  ASSERT_EQ(profile.size(), 16u);
  for (std::size_t i = 0; i < profile.size(); ++i) {
    const double expected_theta = 2 * kPi * static_cast<double>(i) / 16;
    EXPECT_NEAR(profile[i].theta_rad, expected_theta, 1e-13);
    EXPECT_NEAR(profile[i].dr_mm, dr(expected_theta), kFormTol_mm);
    EXPECT_EQ(profile[i].index, (i + 8) % 16);
  }
  double lo = 1, hi = -1;
  for (const auto& s : profile) lo = std::min(lo, s.dr_mm), hi = std::max(hi, s.dr_mm);
  EXPECT_NEAR(ProfileRange(profile), hi - lo, 0.0);
}

TEST(CircularityProfile, PositiveOutward) {
  const fitting::Circle2 c{{0, 0}, 10.0};
  const std::vector<Eigen::Vector2d> pts = {{10.001, 0}, {0, 9.999}};
  const auto p = CircularityProfile(pts, c);
  EXPECT_NEAR(p[0].dr_mm, 0.001, kFormTol_mm);   // theta 0
  EXPECT_NEAR(p[1].dr_mm, -0.001, kFormTol_mm);  // theta 90 deg
}

TEST(LsForm, FlatnessAndStraightness) {
  const fitting::Plane plane{{0, 0, 1}, {0, 0, 1}};
  const std::vector<Eigen::Vector3d> pts = {{0, 0, 1.002}, {5, 0, 0.999}, {0, 5, 1.0}};
  EXPECT_NEAR(LsFlatness(pts, plane), 0.003, kFormTol_mm);

  const fitting::Line2 line{{0, 0}, {1, 0}};
  const std::vector<Eigen::Vector2d> p2 = {{0, 0.001}, {1, -0.002}, {2, 0}};
  EXPECT_NEAR(LsStraightness2(p2, line), 0.003, kFormTol_mm);

  const fitting::Line3 line3{{0, 0, 0}, {0, 0, 1}};
  const std::vector<Eigen::Vector3d> p3 = {{0.003, 0, 0}, {0, -0.001, 5}, {0, 0, 9}};
  EXPECT_NEAR(LsStraightness3(p3, line3), 0.006, kFormTol_mm);  // cylinder diameter
}

}  // namespace
}  // namespace tpcal::gdt
