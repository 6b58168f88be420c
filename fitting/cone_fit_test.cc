#include <gtest/gtest.h>

#include <random>
#include <sstream>

#include "fitting/cylinder_fit.h"
#include "fitting/reference_data.h"
#include "fitting/testing/fit_test_util.h"

namespace tpcal::fitting {
namespace {

using testing::kDirTol_rad;
using testing::kPosTol_mm;
using testing::kSizeTol_mm;

Eigen::Vector3d RandomUnitCone(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Eigen::Vector3d{g(rng), g(rng), g(rng)}.normalized();
}

// Errors of a fitted cone: axis offset at the fitted point, axis angle (directions must
// agree: both point to the wider end) plus half-angle error, and the radius error at the
// fitted point's station.
void ConeScore(const Cone& fit, const Cone& truth, double* pos, double* dir, double* size) {
  *pos = Distance(Line3{truth.point_mm, truth.axis}, fit.point_mm);
  *dir = std::max(testing::DirectionAngle(fit.axis, truth.axis), std::abs(fit.half_angle_rad - truth.half_angle_rad));
  const double w = truth.axis.dot(fit.point_mm - truth.point_mm);
  *size = std::abs(fit.radius_mm - (truth.radius_mm + w * std::tan(truth.half_angle_rad)));
}

// Half angles 5 to 60 deg, radii 1 to 500 mm, full and 120 deg arcs, 1000 mm from the
// origin, 10 to 10^5 points, deviations 0 to 10 um. No axis hint.
TEST(FitCone, CertifiedReferenceData) {
  std::mt19937_64 rng(20240608);
  testing::WorstCase worst("cone");
  for (double half_deg : {5.0, 30.0, 60.0}) {
    for (double radius_mm : {1.0, 10.0, 100.0, 500.0}) {
      for (double arc_deg : {360.0, 120.0}) {
        for (std::size_t n : {10u, 100u, 1000u}) {
          for (double dev_mm : {0.0, 0.001, 0.01}) {
            const double half = DegToRad(half_deg), arc = DegToRad(arc_deg);
            // Axial length: up to 2 R, keeping the apex 20% beyond the sampled band.
            const double length = std::min(2.0 * radius_mm, 0.8 * 2.0 * radius_mm / std::tan(half));
            if (dev_mm > std::min({0.01, 0.01 * radius_mm * arc * arc, 0.01 * length})) continue;
            ReferenceOptions o;
            o.n_points = n;
            o.arc_rad = arc;
            o.length_mm = length;
            o.deviation_rms_mm = dev_mm;
            const Eigen::Vector3d centre = 1000.0 * RandomUnitCone(rng);  // drawn before the axis under every compiler
            const Eigen::Vector3d axis = RandomUnitCone(rng);
            const Cone truth = *MakeCone(centre, axis, half, radius_mm);
            const auto ref = MakeReferenceCone(truth, o, rng);
            ASSERT_TRUE(ref.ok()) << ref.status().ToString();
            std::ostringstream label;
            label << "half " << half_deg << " R " << radius_mm << " arc " << arc_deg << " n " << n << " dev " << dev_mm;
            const auto fit = FitCone(ref->points_mm);
            ASSERT_TRUE(fit.ok()) << label.str() << ": " << fit.status().ToString();
            double res_err = 0.0;
            for (std::size_t i = 0; i < n; ++i) {
              res_err = std::max(res_err, std::abs(fit->residuals_mm[i] - ref->residuals_mm[i]));
            }
            EXPECT_LT(res_err, kSizeTol_mm) << label.str();
            double pos, dir, size;
            ConeScore(fit->feature, truth, &pos, &dir, &size);
            worst.Add(label.str(), pos, dir, size);
          }
        }
      }
    }
  }
  {
    ReferenceOptions o;
    o.n_points = 100000;
    o.length_mm = 30.0;
    o.deviation_rms_mm = 0.002;
    const Eigen::Vector3d centre = 1000.0 * RandomUnitCone(rng);  // drawn before the axis under every compiler
    const Eigen::Vector3d axis = RandomUnitCone(rng);
    const Cone truth = *MakeCone(centre, axis, DegToRad(30.0), 25.0);
    const auto ref = MakeReferenceCone(truth, o, rng);
    ASSERT_TRUE(ref.ok());
    const auto fit = FitCone(ref->points_mm);
    ASSERT_TRUE(fit.ok()) << fit.status().ToString();
    double pos, dir, size;
    ConeScore(fit->feature, truth, &pos, &dir, &size);
    worst.Add("half 30 R 25 n 1e5", pos, dir, size);
  }
  worst.PrintAndCheck();
}

TEST(FitCone, RigidMotionAndOrder) {
  std::mt19937_64 rng(61);
  ReferenceOptions o;
  o.n_points = 300;
  o.arc_rad = DegToRad(180.0);
  o.length_mm = 20.0;
  o.deviation_rms_mm = 0.002;
  const auto ref = MakeReferenceCone(*MakeCone({0, 0, 0}, {0, 0, 1}, DegToRad(20.0), 30.0), o, rng);
  const auto fit = FitCone(ref->points_mm);
  ASSERT_TRUE(fit.ok()) << fit.status().ToString();
  EXPECT_GT(fit->feature.axis.z(), 0.0);  // toward the wider end
  for (int k = 0; k < 3; ++k) {
    const Rigid3 t = testing::RandomRigid(rng, 1000.0);
    const auto moved = FitCone(testing::Apply(t, ref->points_mm));
    ASSERT_TRUE(moved.ok()) << moved.status().ToString();
    EXPECT_LT((moved->feature.point_mm - t * fit->feature.point_mm).norm(), 1e-9);
    EXPECT_LT(testing::DirectionAngle(moved->feature.axis, t.linear() * fit->feature.axis), 1e-10);
    EXPECT_NEAR(moved->feature.half_angle_rad, fit->feature.half_angle_rad, 1e-11);
    EXPECT_NEAR(moved->feature.radius_mm, fit->feature.radius_mm, 1e-9);
  }
  const auto shuffled = FitCone(testing::Shuffled(ref->points_mm, rng));
  ASSERT_TRUE(shuffled.ok());
  EXPECT_LT((shuffled->feature.point_mm - fit->feature.point_mm).norm(), 1e-9);
}

TEST(FitCone, DegenerateInputIsAnError) {
  EXPECT_EQ(FitCone(std::vector<Eigen::Vector3d>(5, Eigen::Vector3d(1, 2, 3))).status().code(),
            StatusCode::kTooFewPoints);
  std::vector<Eigen::Vector3d> flat;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) flat.push_back(Eigen::Vector3d(i * 2.0, j * 3.0, 100.0));
  }
  const auto flat_fit = FitCone(flat);
  EXPECT_FALSE(flat_fit.ok()) << flat_fit->feature;
}

TEST(FitCone, CylinderDataGiveATinyHalfAngleOrAnError) {
  std::mt19937_64 rng(62);
  ReferenceOptions o;
  o.n_points = 200;
  o.length_mm = 40.0;
  o.deviation_rms_mm = 0.0;
  const Cylinder cyl = *MakeCylinder({10, 20, 30}, {0, 1, 0}, 12.0);
  const auto ref = MakeReferenceCylinder(cyl, o, rng);
  const auto fit = FitCone(ref->points_mm);
  if (fit.ok()) {
    EXPECT_LT(fit->feature.half_angle_rad, 1e-9);
    EXPECT_NEAR(fit->feature.radius_mm, 12.0, kSizeTol_mm);
    EXPECT_LT(testing::LineAngle(fit->feature.axis, cyl.axis), kDirTol_rad);
  } else {
    EXPECT_EQ(fit.status().code(), StatusCode::kDegenerate) << fit.status().ToString();
  }
}

}  // namespace
}  // namespace tpcal::fitting
