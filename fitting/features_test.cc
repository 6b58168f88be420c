#include "fitting/features.h"

#include <gtest/gtest.h>

#include <sstream>

#include "core/units.h"
#include "fitting/fit_result.h"

namespace tpcal::fitting {
namespace {

TEST(Features, FactoriesEnforceInvariants) {
  const auto plane = MakePlane({1, 2, 3}, {0, 0, 2});
  ASSERT_TRUE(plane.ok());
  EXPECT_DOUBLE_EQ(plane->normal.norm(), 1.0);
  EXPECT_EQ(MakePlane({0, 0, 0}, {0, 0, 0}).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(MakeLine3({0, 0, NAN}, {1, 0, 0}).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(MakeCircle3({0, 0, 0}, {0, 0, 1}, 0.0).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(MakeCylinder({0, 0, 0}, {0, 0, 1}, -1.0).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(MakeCone({0, 0, 0}, {0, 0, 1}, 0.0, 1.0).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(MakeCone({0, 0, 0}, {0, 0, 1}, kPi / 2, 1.0).status().code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(MakeCone({0, 0, 0}, {0, 0, 1}, 0.3, 1.0).ok());
}

TEST(Features, SignedDistancesFollowTheConventions) {
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  EXPECT_DOUBLE_EQ(Distance(*MakePlane({0, 0, 1}, z), {5, 5, 3}), 2.0);
  EXPECT_DOUBLE_EQ(Distance(Circle2{{1, 1}, 2}, {1, 4}), 1.0);   // outside: positive
  EXPECT_DOUBLE_EQ(Distance(Sphere{{0, 0, 0}, 2}, {0, 1, 0}), -1.0);  // inside: negative
  EXPECT_DOUBLE_EQ(Distance(*MakeCylinder({0, 0, 0}, z, 2.0), {3, 0, 100}), 1.0);
  EXPECT_DOUBLE_EQ(Distance(*MakeCircle3({0, 0, 0}, z, 3.0), {3, 0, 4}), 4.0);
  EXPECT_NEAR(Distance(*MakeCircle3({0, 0, 0}, z, 3.0), {0, 0, 4}), 5.0, 1e-15);
  const Line2 l{{0, 0}, {1, 0}};
  EXPECT_DOUBLE_EQ(SignedDistance(l, {3, 2}), 2.0);  // left of +x is +y
  EXPECT_DOUBLE_EQ(SignedDistance(l, {3, -2}), -2.0);
  EXPECT_DOUBLE_EQ(Distance(l, {3, -2}), 2.0);
  EXPECT_DOUBLE_EQ(Distance(*MakeLine3({0, 0, 0}, {0, 0, 1}), {3, 4, 7}), 5.0);
}

TEST(Features, ConeDistanceIsOrthogonalAndHandlesTheApex) {
  // 45 deg half angle, radius 1 at the origin: apex at z = -1, surface rho = 1 + z.
  const Cone c = *MakeCone({0, 0, 0}, {0, 0, 1}, kPi / 4, 1.0);
  EXPECT_NEAR(Distance(c, {1, 0, 0}), 0.0, 1e-15);
  EXPECT_NEAR(Distance(c, {3, 0, 0}), 2.0 * std::cos(kPi / 4), 1e-15);  // outside
  EXPECT_NEAR(Distance(c, {0, 0, 0}), -std::cos(kPi / 4), 1e-15);       // on the axis, inside
  EXPECT_NEAR(Distance(c, {0, 0, -3}), 2.0, 1e-15);                     // behind the apex
  // Moving a surface point along the surface normal by d gives distance d.
  const Eigen::Vector3d foot(2.0, 0.0, 1.0), normal = Eigen::Vector3d(1, 0, -1).normalized();
  EXPECT_NEAR(Distance(c, foot + 0.3 * normal), 0.3, 1e-15);
}

TEST(Features, SameDirectionIgnoresSignAndFailsOnNan) {
  EXPECT_TRUE(SameDirection({0, 0, 1}, {0, 0, -1}, 1e-12));
  EXPECT_TRUE(SameDirection({0, 0, 1}, Eigen::Vector3d(1e-7, 0, 1).normalized(), 2e-7));
  EXPECT_FALSE(SameDirection({0, 0, 1}, Eigen::Vector3d(1e-6, 0, 1).normalized(), 1e-7));
  EXPECT_FALSE(SameDirection({0, 0, 1}, {NAN, 0, 1}, 1.0));
}

TEST(Features, PrintWithNamedFields) {
  std::ostringstream os;
  os << Circle2{{1, 2}, 3};
  EXPECT_EQ(os.str(), "Circle2{center_mm=(1, 2), radius_mm=3}");
  os.str("");
  os << *MakeCone({0, 0, 0}, {0, 0, 1}, 0.5, 2.0);
  EXPECT_EQ(os.str(), "Cone{point_mm=(0, 0, 0), axis=(0, 0, 1), half_angle_rad=0.5, radius_mm=2}");
}

TEST(FitResult, TerminationNamesAndOptionValidation) {
  EXPECT_STREQ(TerminationName(Termination::kClosedForm), "closed_form");
  EXPECT_STREQ(TerminationName(Termination::kConverged), "converged");
  EXPECT_STREQ(TerminationName(Termination::kMaxIterations), "max_iterations");
  EXPECT_TRUE(FitOptions{}.Validate().ok());
  FitOptions o;
  o.step_tolerance_mm = 0.0;
  EXPECT_EQ(o.Validate().code(), StatusCode::kInvalidArgument);
  o.step_tolerance_mm = 1e-2;
  EXPECT_EQ(o.Validate().code(), StatusCode::kInvalidArgument);
  o = FitOptions{};
  o.max_iterations = 0;
  EXPECT_EQ(o.Validate().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace tpcal::fitting
