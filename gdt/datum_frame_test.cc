// Datum frames recovered from exact features placed anywhere on the CMM.
#include "gdt/datum_frame.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/units.h"
#include "fitting/plane_fit.h"
#include "gdt/synthetic.h"

namespace tpcal::gdt {
namespace {

// Exact data: coordinates up to ~1000 mm after placement carry ~1e-13 mm of rounding through
// the fits and transforms; 1e-9 mm / 1e-9 rad (the brief's bound) leaves a wide margin.
constexpr double kFrameTol_mm = 1e-9;
constexpr double kFrameTol_rad = 1e-9;
constexpr double kDatumMaxTranslation_mm = 1000.0;

// Rotation angle of a^-1 b and distance between the translations.
void ExpectSameFrame(const Rigid3& a, const Rigid3& b) {
  const Eigen::AngleAxisd d(a.linear().transpose() * b.linear());
  EXPECT_LT(std::abs(d.angle()), kFrameTol_rad);
  EXPECT_LT((a.translation() - b.translation()).norm(), kFrameTol_mm);
}

std::vector<Eigen::Vector3d> Transform(const std::vector<Eigen::Vector3d>& pts, const Rigid3& t) {
  std::vector<Eigen::Vector3d> out;
  for (const auto& p : pts) out.push_back(t * p);
  return out;
}

TEST(OrientAlong, FlipsToTheSenseAndRejectsUndecidedSenses) {
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  EXPECT_EQ(*OrientAlong(z, Eigen::Vector3d(0.1, 0, -5), "z"), -z);
  EXPECT_EQ(*OrientAlong(z, Eigen::Vector3d(0.1, 0, 5), "z"), z);
  EXPECT_EQ(OrientAlong(z, Eigen::Vector3d(1, 0, 0), "z").status().code(), StatusCode::kDegenerate);
  EXPECT_EQ(OrientAlong(z, Eigen::Vector3d::Zero(), "z").status().code(), StatusCode::kDegenerate);
}

TEST(DatumFromAxes, IsRightHandedWithTheGivenOriginAndAxes) {
  const Eigen::Vector3d origin(10, 20, 30);
  const Eigen::Vector3d z = Eigen::Vector3d(1, 1, 1).normalized();
  auto t = DatumFromAxes(origin, z, Eigen::Vector3d(1, 0, 0));
  ASSERT_TRUE(t.ok());
  EXPECT_LT((*t * origin).norm(), 1e-12);
  EXPECT_LT((t->linear() * z - Eigen::Vector3d::UnitZ()).norm(), 1e-15);
  EXPECT_NEAR(t->linear().determinant(), 1.0, 1e-15);
  // The x direction's component along z is ignored: it lands in the datum XZ plane, +X side.
  const Eigen::Vector3d x_in_datum = t->linear() * Eigen::Vector3d(1, 0, 0);
  EXPECT_NEAR(x_in_datum.y(), 0.0, 1e-15);
  EXPECT_GT(x_in_datum.x(), 0.0);
  EXPECT_EQ(DatumFromAxes(origin, z, z * 3).status().code(), StatusCode::kDegenerate);
}

// Seed 002 turning frame. Truth: the part frame P is the datum frame (B_R on z = 0, S_R centred
// on the Z axis, H1 on +X). S_R is probed at scattered heights: the projected centre must not
// care, which a 3D circle through those points would.
TEST(TurningDatumFromCmm, RecoversThePartFrameFromAnyPlacement) {
  PointSet part;
  AppendPlaneRing(&part, "B_R", {.center_mm = {0, 0, 0}, .normal = {0, 0, 1}, .radius_mm = 130.0});
  std::vector<Eigen::Vector3d> s_r;
  std::mt19937_64 heights(7);
  std::uniform_real_distribution<double> z(1.0, 5.0);
  for (int k = 0; k < 16; ++k) {
    const double t = 2 * kPi * k / 16;
    s_r.emplace_back(119.0 * std::cos(t), 119.0 * std::sin(t), z(heights));
  }
  AppendCircle(&part, "H1", {.center_mm = {140, 0, -3}, .radius_mm = 5.35, .n_points = 8, .hole = true});

  std::mt19937_64 rng(20240531);
  for (int trial = 0; trial < 5; ++trial) {
    const Rigid3 cmm_from_part = RandomPlacement(rng, kDatumMaxTranslation_mm);
    const PointSet cmm = Transformed(part, cmm_from_part);
    auto plane = fitting::FitPlane(cmm.PointsOf("B_R"));
    ASSERT_TRUE(plane.ok()) << plane.status().ToString();
    fitting::Plane primary = plane->feature;
    // +Z of the part, from a part-intrinsic reference (here: a point 245 mm below B_R).
    primary.normal = *OrientAlong(primary.normal, primary.point_mm - cmm_from_part * Eigen::Vector3d(0, 0, -245), "Z");
    auto center = ProjectedCircleCenter(Transform(s_r, cmm_from_part), primary);
    ASSERT_TRUE(center.ok()) << center.status().ToString();
    auto h1 = ProjectedCircleCenter(cmm.PointsOf("H1"), primary);
    ASSERT_TRUE(h1.ok());
    auto frame = TurningDatumFromCmm(primary, *center, *h1);
    ASSERT_TRUE(frame.ok()) << frame.status().ToString();
    ExpectSameFrame(*frame, cmm_from_part.inverse());
  }
}

TEST(TurningDatumFromCmm, XTargetOnTheOriginIsDegenerate) {
  const fitting::Plane p{{0, 0, 0}, {0, 0, 1}};
  auto f = TurningDatumFromCmm(p, {1, 2, 0}, {1, 2, 7});
  EXPECT_EQ(f.status().code(), StatusCode::kDegenerate);
}

TEST(ThreeTwoOneDatumFromCmm, OriginAtTheFootOfTheTertiaryPoint) {
  // Part frame: primary z = 0; secondary line on a side face at height 7, running along +X at
  // y = 0 and rising slightly (its projection is what counts); tertiary point at x = -3.
  const fitting::Plane primary_p{{0, 0, 0}, {0, 0, 1}};
  const fitting::Line3 secondary_p{{5, 0, 7}, Eigen::Vector3d(1, 0, 0.01).normalized()};
  const Eigen::Vector3d tertiary_p(-3, 20, 4);
  const Rigid3 datum_from_part = MakeRigid(Eigen::Matrix3d::Identity(), Eigen::Vector3d(3, 0, 0));

  std::mt19937_64 rng(42);
  for (int trial = 0; trial < 5; ++trial) {
    const Rigid3 cmm_from_part = RandomPlacement(rng, kDatumMaxTranslation_mm);
    const fitting::Plane primary{cmm_from_part * primary_p.point_mm, cmm_from_part.linear() * primary_p.normal};
    const fitting::Line3 secondary{cmm_from_part * secondary_p.point_mm, cmm_from_part.linear() * secondary_p.direction};
    auto frame = ThreeTwoOneDatumFromCmm(primary, secondary, cmm_from_part * tertiary_p);
    ASSERT_TRUE(frame.ok());
    ExpectSameFrame(*frame, datum_from_part * cmm_from_part.inverse());
  }
}

TEST(ThreeTwoOneDatumFromCmm, SecondaryAlongThePrimaryNormalIsDegenerate) {
  const fitting::Plane p{{0, 0, 0}, {0, 0, 1}};
  const fitting::Line3 l{{0, 0, 0}, {0, 0, 1}};
  EXPECT_EQ(ThreeTwoOneDatumFromCmm(p, l, {1, 1, 1}).status().code(), StatusCode::kDegenerate);
}

TEST(TargetsDatumFromCmm, YTowardTheSecondTargetOriginOnThePrimary) {
  // Part frame: primary z = 2 (normal +Z); centre target at (1, -4, 5) -> origin (1, -4, 2);
  // y target at (1, 30, -1): +Y along part +Y, so datum = part shifted by (1, -4, 2).
  const fitting::Plane primary_p{{0, 0, 2}, {0, 0, 1}};
  const Eigen::Vector3d center_p(1, -4, 5), target_p(1, 30, -1);
  const Rigid3 datum_from_part = MakeRigid(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-1, 4, -2));
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 5; ++trial) {
    const Rigid3 cmm_from_part = RandomPlacement(rng, kDatumMaxTranslation_mm);
    const fitting::Plane primary{cmm_from_part * primary_p.point_mm, cmm_from_part.linear() * primary_p.normal};
    auto y = TargetsDatumFromCmm(primary, cmm_from_part * center_p, cmm_from_part * target_p, true);
    ASSERT_TRUE(y.ok());
    ExpectSameFrame(*y, datum_from_part * cmm_from_part.inverse());
    // The same target as +X: the frame turned -90 deg about Z (datum X = part Y).
    auto x = TargetsDatumFromCmm(primary, cmm_from_part * center_p, cmm_from_part * target_p, false);
    ASSERT_TRUE(x.ok());
    ExpectSameFrame(*x, MakeRigid(RotZ(-kPi / 2), Eigen::Vector3d::Zero()) * datum_from_part * cmm_from_part.inverse());
  }
  EXPECT_EQ(TargetsDatumFromCmm(primary_p, center_p, Eigen::Vector3d(1, -4, 9), true).status().code(),
            StatusCode::kDegenerate);
}

}  // namespace
}  // namespace tpcal::gdt
