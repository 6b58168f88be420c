// Sign conventions of gdt/location.h.
#include "gdt/location.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

namespace tpcal::gdt {
namespace {

constexpr double kLocationTol_mm = 1e-12;  // closed-form arithmetic on coordinates below 1000 mm

TEST(InPlane, CoordinatesAreRightHandedAboutThePlaneNormal) {
  const Eigen::Vector3d p(1, 2, 3);
  EXPECT_EQ(InPlane(p, Projection::kDatumXY), Eigen::Vector2d(1, 2));
  EXPECT_EQ(InPlane(p, Projection::kDatumYZ), Eigen::Vector2d(2, 3));
  EXPECT_EQ(InPlane(p, Projection::kDatumZX), Eigen::Vector2d(3, 1));
  for (Projection pr : {Projection::kDatumXY, Projection::kDatumYZ, Projection::kDatumZX}) {
    EXPECT_EQ(FromPlane(InPlane(p, pr), AlongNormal(p, pr), pr), p) << ProjectionName(pr);
    // (u axis) x (v axis) = plane normal.
    const Eigen::Vector3d u = FromPlane({1, 0}, 0, pr), v = FromPlane({0, 1}, 0, pr);
    EXPECT_EQ(u.cross(v), PlaneNormal(pr)) << ProjectionName(pr);
  }
}

TEST(CenterOffset, IsFeatureMinusDatum) {
  // Seed 002 #5: S4's centre at (+12.9, -23.3) um from S_R's gives (dx, dy) = (12.9, -23.3) um.
  const PlanarOffset o = CenterOffset({0.0129, -0.0233}, {0.0, 0.0});
  EXPECT_NEAR(o.delta_mm.x(), 0.0129, kLocationTol_mm);
  EXPECT_NEAR(o.delta_mm.y(), -0.0233, kLocationTol_mm);
  EXPECT_NEAR(o.zone_diameter_mm, 2 * std::hypot(0.0129, 0.0233), kLocationTol_mm);
  const PlanarOffset r = CenterOffset({0.0, 0.0}, {0.0129, -0.0233});
  EXPECT_NEAR(r.delta_mm.x(), -0.0129, kLocationTol_mm);
}

TEST(PlaneDistance, SignedAlongTheDatumNormal) {
  const fitting::Plane datum{{0, 0, 0}, {0, 0, 1}};
  // A face 25 mm below the datum, 23 um higher than nominal.
  const fitting::Plane b3{{10, -40, -25.0 + 0.023}, {0, 0, 1}};
  const PlaneDistanceResult r = PlaneDistance(b3, datum, -25.0);
  EXPECT_NEAR(r.distance_mm, -24.977, kLocationTol_mm);
  EXPECT_NEAR(r.error_mm, 0.023, kLocationTol_mm);
  EXPECT_NEAR(r.separation_error_mm, -0.023, kLocationTol_mm);  // closer to the datum than nominal
  // The feature's normal sense does not matter; the datum's does.
  const fitting::Plane b3_flipped{b3.point_mm, {0, 0, -1}};
  EXPECT_NEAR(PlaneDistance(b3_flipped, datum, -25.0).error_mm, 0.023, kLocationTol_mm);
  const fitting::Plane datum_down{{0, 0, 0}, {0, 0, -1}};
  EXPECT_NEAR(PlaneDistance(b3, datum_down, 25.0).error_mm, -0.023, kLocationTol_mm);
}

}  // namespace
}  // namespace tpcal::gdt
