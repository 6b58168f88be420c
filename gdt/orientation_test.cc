// Sign conventions of gdt/orientation.h, checked against rotations built with core/frames.h.
#include "gdt/orientation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/frames.h"
#include "core/units.h"

namespace tpcal::gdt {
namespace {

// Closed-form geometry in double precision: angles agree to a few ulp of 1 rad.
constexpr double kOrientationAngleTol_rad = 1e-14;
// Zone widths over a 160 mm ring: a few ulp of the coordinates.
constexpr double kZoneTol_mm = 1e-12;

const Eigen::Vector3d kX = Eigen::Vector3d::UnitX();
const Eigen::Vector3d kY = Eigen::Vector3d::UnitY();
const Eigen::Vector3d kZ = Eigen::Vector3d::UnitZ();

// Three regimes: tiny, the size of seed 002's tilts (8.7 urad), and large.
const double kAngles[] = {1e-9, 8.7e-6, -1.7e-6, 0.1, -0.3};

TEST(TiltOf, RotationAboutXOfTheDatumNormalGivesDaOnly) {
  for (double a : kAngles) {
    const TiltAngles t = TiltOf(RotX(a) * kZ, kZ);
    EXPECT_EQ(t.axis_i, 0);  // about X
    EXPECT_EQ(t.axis_j, 1);  // about Y
    EXPECT_NEAR(t.about_i_rad, a, kOrientationAngleTol_rad);
    EXPECT_NEAR(t.about_j_rad, 0.0, kOrientationAngleTol_rad);
    EXPECT_NEAR(t.total_rad, std::abs(a), kOrientationAngleTol_rad);
  }
}

TEST(TiltOf, RotationAboutYOfTheDatumNormalGivesDbOnly) {
  for (double b : kAngles) {
    const TiltAngles t = TiltOf(RotY(b) * kZ, kZ);
    EXPECT_NEAR(t.about_i_rad, 0.0, kOrientationAngleTol_rad);
    EXPECT_NEAR(t.about_j_rad, b, kOrientationAngleTol_rad);
  }
}

TEST(TiltOf, SlopeFormOfTheSignRule) {
  // A face z = s_y * y rises toward +Y: da = atan(s_y) > 0. A face z = s_x * x: db = -atan(s_x).
  const double s = 2e-5;
  const Eigen::Vector3d n_rising_y = Eigen::Vector3d(0, -s, 1).normalized();
  EXPECT_NEAR(TiltOf(n_rising_y, kZ).about_i_rad, std::atan(s), kOrientationAngleTol_rad);
  const Eigen::Vector3d n_rising_x = Eigen::Vector3d(-s, 0, 1).normalized();
  EXPECT_NEAR(TiltOf(n_rising_x, kZ).about_j_rad, -std::atan(s), kOrientationAngleTol_rad);
}

TEST(TiltOf, OppositeNormalIsTheSamePlane) {
  const TiltAngles a = TiltOf(RotX(3e-6) * kZ, kZ);
  const TiltAngles b = TiltOf(-(RotX(3e-6) * kZ), kZ);
  EXPECT_NEAR(a.about_i_rad, b.about_i_rad, kOrientationAngleTol_rad);
  EXPECT_NEAR(a.about_j_rad, b.about_j_rad, kOrientationAngleTol_rad);
}

TEST(TiltOf, DominantXAndYDatumAxesUseTheCyclicPairs) {
  // Datum along X: angles about Y (b) then Z (c).
  TiltAngles t = TiltOf(RotY(4e-6) * kX, kX);
  EXPECT_EQ(t.axis_i, 1);
  EXPECT_EQ(t.axis_j, 2);
  EXPECT_NEAR(t.about_i_rad, 4e-6, kOrientationAngleTol_rad);
  t = TiltOf(RotZ(-5e-6) * kX, kX);
  EXPECT_NEAR(t.about_j_rad, -5e-6, kOrientationAngleTol_rad);
  // Datum along Y: angles about Z (c) then X (a).
  t = TiltOf(RotZ(6e-6) * kY, kY);
  EXPECT_EQ(t.axis_i, 2);
  EXPECT_EQ(t.axis_j, 0);
  EXPECT_NEAR(t.about_i_rad, 6e-6, kOrientationAngleTol_rad);
  t = TiltOf(RotX(7e-6) * kY, kY);
  EXPECT_NEAR(t.about_j_rad, 7e-6, kOrientationAngleTol_rad);
}

TEST(TiltOf, AnglesAreRelativeToATiltedDatum) {
  const Eigen::Vector3d v = RotX(2e-6) * kZ;
  const TiltAngles t = TiltOf(RotX(5e-6) * kZ, v);
  EXPECT_NEAR(t.about_i_rad, 3e-6, kOrientationAngleTol_rad);
}

std::vector<Eigen::Vector3d> Ring(double radius, double z, const Eigen::Matrix3d& r = Eigen::Matrix3d::Identity()) {
  std::vector<Eigen::Vector3d> pts;
  for (int k = 0; k < 16; ++k) {
    const double t = 2 * kPi * k / 16;
    pts.push_back(r * Eigen::Vector3d(radius * std::cos(t), radius * std::sin(t), 0) + Eigen::Vector3d(0, 0, z));
  }
  return pts;
}

TEST(PlaneParallelism, ZoneIsTheTiltOverTheFeatureWidth) {
  const double a = 8.7e-6, radius = 162.5;
  const Eigen::Matrix3d r = RotX(a);
  const auto pts = Ring(radius, -5.0, r);
  const ParallelismResult p = PlaneParallelism(r * kZ, Eigen::Vector3d(0, 0, -5.0), kZ, pts);
  EXPECT_NEAR(p.tilt.about_i_rad, a, kOrientationAngleTol_rad);
  // The ring's points at +-Y are 2 R apart along Y: the zone is 2 R sin(a).
  EXPECT_NEAR(p.zone_mm, 2 * radius * std::sin(a), kZoneTol_mm);
  EXPECT_NEAR(p.tilt_zone_mm, 2 * radius * std::sin(a), kZoneTol_mm);
}

TEST(PlaneParallelism, ZoneIncludesFormTiltZoneDoesNot) {
  auto pts = Ring(100.0, 0.0);
  pts[3].z() += 0.002;  // a 2 um bump on a perfectly parallel face
  const ParallelismResult p = PlaneParallelism(kZ, Eigen::Vector3d::Zero(), kZ, pts);
  EXPECT_NEAR(p.zone_mm, 0.002, kZoneTol_mm);
  EXPECT_NEAR(p.tilt_zone_mm, 0.0, kZoneTol_mm);
}

TEST(Squareness, PlaneToPlaneAngleIsPositiveBelowNinetyDegrees) {
  // u at 90 deg - d from v: u.v = sin(d) > 0.
  const double d = 12e-6;
  const Eigen::Vector3d u = RotY(-d) * kX;  // tips +X toward +Z by d
  ASSERT_GT(u.dot(kZ), 0.0);
  std::vector<Eigen::Vector3d> face;  // a face x = 0 tilted with u, extent 50 mm along z
  for (double z : {0.0, 50.0})
    for (double y : {-20.0, 20.0}) face.push_back(RotY(-d) * Eigen::Vector3d(0, y, z));
  auto r = EvaluateSquareness(DirectedKind::kPlaneNormal, u, face, DirectedKind::kPlaneNormal, kZ);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  ASSERT_TRUE(r->angle_rad.has_value());
  EXPECT_NEAR(*r->angle_rad, d, kOrientationAngleTol_rad);
  EXPECT_NEAR(r->zone_mm, 50.0 * std::sin(d), kZoneTol_mm);
  // Flipping the datum's sense flips the sign: the sense rules of the plan matter.
  auto flipped = EvaluateSquareness(DirectedKind::kPlaneNormal, u, face, DirectedKind::kPlaneNormal, -kZ);
  EXPECT_NEAR(*flipped->angle_rad, -d, kOrientationAngleTol_rad);
}

TEST(Squareness, AxisToPlaneGivesTiltComponents) {
  const double a = 3e-6;
  const Eigen::Vector3d u = RotX(a) * kZ;
  const std::vector<Eigen::Vector3d> axis_points = {Eigen::Vector3d::Zero(), u * 80.0};
  auto r = EvaluateSquareness(DirectedKind::kAxis, u, axis_points, DirectedKind::kPlaneNormal, kZ);
  ASSERT_TRUE(r.ok());
  ASSERT_TRUE(r->tilt.has_value());
  EXPECT_NEAR(r->tilt->about_i_rad, a, kOrientationAngleTol_rad);
  EXPECT_NEAR(r->zone_mm, 80.0 * std::sin(a), kZoneTol_mm);
}

TEST(Squareness, ParallelPlanesAreDegenerate) {
  auto r = EvaluateSquareness(DirectedKind::kPlaneNormal, kZ, Ring(10, 0), DirectedKind::kPlaneNormal, kZ);
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kDegenerate);
}

}  // namespace
}  // namespace tpcal::gdt
