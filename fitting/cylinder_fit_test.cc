#include "fitting/cylinder_fit.h"

#include <gtest/gtest.h>

#include <random>
#include <sstream>

#include "fitting/reference_data.h"
#include "fitting/testing/fit_test_util.h"

namespace tpcal::fitting {
namespace {

using testing::kDirTol_rad;
using testing::kPosTol_mm;
using testing::kSizeTol_mm;
using testing::LineAngle;

Eigen::Vector3d RandomUnitCylinder(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Eigen::Vector3d{g(rng), g(rng), g(rng)}.normalized();
}

// Radii 1 to 500 mm, arcs 360 down to 20 deg, lengths 0.2 R and 2 R, axes 1000 mm from the
// origin in random directions, 10 to 10^5 points, deviations 0 to 10 um (certifiable: at
// most 1% of R x arc^2 and of the length). No axis hint: the start search is under test.
TEST(FitCylinder, CertifiedReferenceData) {
  std::mt19937_64 rng(20240607);
  testing::WorstCase worst("cylinder");
  for (double radius_mm : {1.0, 10.0, 100.0, 500.0}) {
    for (double arc_deg : {360.0, 90.0, 20.0}) {
      for (double length_ratio : {0.2, 2.0}) {
        for (std::size_t n : {10u, 100u, 1000u}) {
          for (double dev_mm : {0.0, 0.001, 0.01}) {
            const double arc = DegToRad(arc_deg), length = length_ratio * radius_mm;
            if (dev_mm > std::min({0.01, 0.01 * radius_mm * arc * arc, 0.01 * length})) continue;
            ReferenceOptions o;
            o.n_points = n;
            o.arc_rad = arc;
            o.arc_start_rad = std::uniform_real_distribution<double>(0, 2 * kPi)(rng);
            o.length_mm = length;
            o.deviation_rms_mm = dev_mm;
            const Eigen::Vector3d point = 1000.0 * RandomUnitCylinder(rng);  // drawn before the axis under every compiler
            const Eigen::Vector3d axis = RandomUnitCylinder(rng);
            const Cylinder truth = *MakeCylinder(point, axis, radius_mm);
            const auto ref = MakeReferenceCylinder(truth, o, rng);
            ASSERT_TRUE(ref.ok()) << ref.status().ToString();
            std::ostringstream label;
            label << "R " << radius_mm << " arc " << arc_deg << " L " << length << " n " << n << " dev " << dev_mm;
            const auto fit = FitCylinder(ref->points_mm);
            ASSERT_TRUE(fit.ok()) << label.str() << ": " << fit.status().ToString();
            double res_err = 0.0;
            for (std::size_t i = 0; i < n; ++i) {
              res_err = std::max(res_err, std::abs(fit->residuals_mm[i] - ref->residuals_mm[i]));
            }
            EXPECT_LT(res_err, kSizeTol_mm) << label.str();
            worst.Add(label.str(), Distance(Line3{truth.point_mm, truth.axis}, fit->feature.point_mm),
                      LineAngle(fit->feature.axis, truth.axis), std::abs(fit->feature.radius_mm - radius_mm));
          }
        }
      }
    }
  }
  for (double arc_deg : {360.0, 20.0}) {
    ReferenceOptions o;
    o.n_points = 100000;
    o.arc_rad = DegToRad(arc_deg);
    o.length_mm = 80.0;
    o.deviation_rms_mm = 0.002;
    const Eigen::Vector3d point = 1000.0 * RandomUnitCylinder(rng);  // drawn before the axis under every compiler
    const Eigen::Vector3d axis = RandomUnitCylinder(rng);
    const Cylinder truth = *MakeCylinder(point, axis, 40.0);
    const auto ref = MakeReferenceCylinder(truth, o, rng);
    ASSERT_TRUE(ref.ok());
    const auto fit = FitCylinder(ref->points_mm);
    ASSERT_TRUE(fit.ok()) << fit.status().ToString();
    worst.Add("R 40 L 80 n 1e5 arc " + std::to_string(arc_deg),
              Distance(Line3{truth.point_mm, truth.axis}, fit->feature.point_mm), LineAngle(fit->feature.axis, truth.axis),
              std::abs(fit->feature.radius_mm - 40.0));
  }
  worst.PrintAndCheck();
}

TEST(FitCylinder, HintSetsSignAndGivesSameFit) {
  std::mt19937_64 rng(51);
  ReferenceOptions o;
  o.n_points = 200;
  o.arc_rad = DegToRad(60.0);
  o.length_mm = 30.0;
  o.deviation_rms_mm = 0.003;
  const Cylinder truth = *MakeCylinder({100, 200, 300}, {1, -2, 0.5}, 15.0);
  const auto ref = MakeReferenceCylinder(truth, o, rng);
  const auto free_fit = FitCylinder(ref->points_mm);
  const auto hinted = FitCylinder(ref->points_mm, {}, -truth.axis);
  ASSERT_TRUE(free_fit.ok() && hinted.ok());
  EXPECT_LT(hinted->feature.axis.dot(truth.axis), 0.0);
  EXPECT_GT(free_fit->feature.axis.z(), 0.0);  // default sign rule
  EXPECT_LT(LineAngle(free_fit->feature.axis, hinted->feature.axis), 1e-12);
  EXPECT_LT((free_fit->feature.point_mm - hinted->feature.point_mm).norm(), 1e-10);
  // The (u, v) frames may differ by a rotation about the axis: compare what does not
  // depend on it (traces of the offset and tilt blocks, the radius variance).
  const Eigen::MatrixXd& a = hinted->covariance;
  const Eigen::MatrixXd& b = free_fit->covariance;
  EXPECT_NEAR(a.topLeftCorner(2, 2).trace() / b.topLeftCorner(2, 2).trace(), 1.0, 1e-8);
  EXPECT_NEAR(a.block(2, 2, 2, 2).trace() / b.block(2, 2, 2, 2).trace(), 1.0, 1e-8);
  EXPECT_NEAR(a(4, 4) / b(4, 4), 1.0, 1e-8);
  EXPECT_NEAR(hinted->local_axes.determinant(), 1.0, 1e-12);
}

TEST(FitCylinder, RigidMotionAndOrder) {
  std::mt19937_64 rng(52);
  ReferenceOptions o;
  o.n_points = 300;
  o.arc_rad = DegToRad(20.0);
  o.length_mm = 50.0;
  o.deviation_rms_mm = 0.001;
  const auto ref = MakeReferenceCylinder(*MakeCylinder({0, 0, 0}, {0, 0, 1}, 25.0), o, rng);
  const auto fit = FitCylinder(ref->points_mm);
  ASSERT_TRUE(fit.ok()) << fit.status().ToString();
  for (int k = 0; k < 3; ++k) {
    const Rigid3 t = testing::RandomRigid(rng, 1000.0);
    const auto moved = FitCylinder(testing::Apply(t, ref->points_mm), {}, t.linear() * fit->feature.axis);
    ASSERT_TRUE(moved.ok()) << moved.status().ToString();
    EXPECT_LT((moved->feature.point_mm - t * fit->feature.point_mm).norm(), 1e-9);
    EXPECT_LT(testing::DirectionAngle(moved->feature.axis, t.linear() * fit->feature.axis), 1e-10);
    EXPECT_NEAR(moved->feature.radius_mm, fit->feature.radius_mm, 1e-9);
    for (std::size_t i = 0; i < ref->points_mm.size(); ++i) ASSERT_NEAR(moved->residuals_mm[i], fit->residuals_mm[i], 1e-10);
  }
  const auto shuffled = FitCylinder(testing::Shuffled(ref->points_mm, rng));
  ASSERT_TRUE(shuffled.ok());
  EXPECT_LT((shuffled->feature.point_mm - fit->feature.point_mm).norm(), 1e-9);
  EXPECT_LT(LineAngle(shuffled->feature.axis, fit->feature.axis), 1e-11);
}

TEST(FitCylinder, DegenerateInputIsAnErrorOrCorrect) {
  EXPECT_EQ(FitCylinder(std::vector<Eigen::Vector3d>(4, Eigen::Vector3d(1, 2, 3))).status().code(),
            StatusCode::kTooFewPoints);
  EXPECT_EQ(FitCylinder(std::vector<Eigen::Vector3d>(8, Eigen::Vector3d(1, 2, 3))).status().code(),
            StatusCode::kDegenerate);
  // One ring of points: the axis direction is not determined (tilts change no distance to
  // first order).
  std::vector<Eigen::Vector3d> ring;
  for (int k = 0; k < 16; ++k) ring.push_back(Eigen::Vector3d(500 + 10 * std::cos(k * 0.4), 10 * std::sin(k * 0.4), 3.0));
  const auto ring_fit = FitCylinder(ring, {}, Eigen::Vector3d::UnitZ());
  EXPECT_EQ(ring_fit.status().code(), StatusCode::kDegenerate) << ring_fit.status().ToString();
  // A flat grid: no finite radius.
  std::vector<Eigen::Vector3d> flat;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) flat.push_back(Eigen::Vector3d(i * 2.0, j * 3.0, 100.0));
  }
  const auto flat_fit = FitCylinder(flat);
  EXPECT_FALSE(flat_fit.ok()) << flat_fit->feature;
  // A 5 deg arc without noise: exact, or a clear error; never a wrong cylinder.
  std::mt19937_64 rng(53);
  ReferenceOptions o;
  o.n_points = 60;
  o.arc_rad = DegToRad(5.0);
  o.length_mm = 40.0;
  o.deviation_rms_mm = 0.0;
  const Cylinder truth = *MakeCylinder({-1000, 0, 0}, {0.3, 0.4, 1.0}, 50.0);
  const auto ref = MakeReferenceCylinder(truth, o, rng);
  const auto short_arc = FitCylinder(ref->points_mm);
  if (short_arc.ok()) {
    EXPECT_LT(LineAngle(short_arc->feature.axis, truth.axis), kDirTol_rad);
    EXPECT_NEAR(short_arc->feature.radius_mm, 50.0, kSizeTol_mm);
  } else {
    EXPECT_EQ(short_arc.status().code(), StatusCode::kDegenerate);
  }
}

// Covariance against the scatter of repeated fits on a 120 deg arc (1000 trials: variances
// within 4 sqrt(2/1000) = 18%).
TEST(FitCylinder, CovarianceMatchesMonteCarlo) {
  std::mt19937_64 rng(54);
  const Cylinder truth = *MakeCylinder({0, 0, 0}, {0, 0, 1}, 20.0);
  std::normal_distribution<double> noise(0.0, 0.002);
  std::uniform_real_distribution<double> angle(0.0, DegToRad(120.0)), height(-15.0, 15.0);
  std::vector<Eigen::Vector3d> nominal;
  for (int i = 0; i < 60; ++i) {
    const double a = angle(rng);
    nominal.push_back(Eigen::Vector3d(20.0 * std::cos(a), 20.0 * std::sin(a), height(rng)));
  }
  const int trials = 1000;
  Eigen::VectorXd emp = Eigen::VectorXd::Zero(5), reported = Eigen::VectorXd::Zero(5);
  for (int t = 0; t < trials; ++t) {
    std::vector<Eigen::Vector3d> p = nominal;
    for (auto& x : p) x += noise(rng) * Eigen::Vector3d(x.x(), x.y(), 0.0).normalized();
    const auto fit = FitCylinder(p, {}, truth.axis);
    ASSERT_TRUE(fit.ok());
    // The true cylinder in the fit's parameters: offsets of the true axis at the fit's
    // point, tilts of the true axis, radius.
    const Eigen::Matrix3d f = fit->local_axes;
    const Eigen::Vector3d foot = truth.point_mm + truth.axis.dot(fit->feature.point_mm - truth.point_mm) * truth.axis;
    const Eigen::Vector3d off = foot - fit->feature.point_mm;
    Eigen::VectorXd d(5);
    d << f.col(0).dot(off), f.col(1).dot(off), f.col(0).dot(truth.axis), f.col(1).dot(truth.axis),
        truth.radius_mm - fit->feature.radius_mm;
    emp += d.cwiseAbs2();
    reported += fit->covariance.diagonal();
  }
  for (int k = 0; k < 5; ++k) EXPECT_NEAR(emp[k] / reported[k], 1.0, 0.18) << "parameter " << k;
}

}  // namespace
}  // namespace tpcal::fitting
