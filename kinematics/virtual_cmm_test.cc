// Virtual CMM: noise statistics along the normal, probe-radius shift, random placement returned
// and consistent, deterministic for a seed, clear failures.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "kinematics/virtual_cmm.h"

namespace tpcal::kinematics {
namespace {

PointSet Cylinder(int n, double r) {
  PointSet p;
  p.source = "cylinder";
  const int f = p.InternFeature("S1");
  for (int i = 0; i < n; ++i) {
    const double t = 2 * 3.14159265358979 * i / n;
    p.xyz_mm.emplace_back(r * std::cos(t), r * std::sin(t), 0.1 * (i % 50));
    p.normal.emplace_back(std::cos(t), std::sin(t), 0.0);
    p.feature.push_back(f);
  }
  return p;
}

TEST(VirtualCmm, NoiseAlongNormalHasTheRequestedSigma) {
  // Truth: N(0, 2 um) along the normal. With n = 20000 the sample sigma is within 3 % (about
  // 6 standard errors) and the mean within 0.1 um.
  const PointSet in = Cylinder(20000, 160.0);
  VirtualCmmOptions o;
  o.noise_sigma_um = 2.0;
  std::mt19937_64 rng(41);
  Result<VirtualCmmResult> r = MeasureWithVirtualCmm(in, o, rng);
  ASSERT_TRUE(r.ok());
  double sum = 0, sum2 = 0;
  for (size_t i = 0; i < in.size(); ++i) {
    const double d_um = 1e3 * in.normal[i].dot(r->points.xyz_mm[i] - in.xyz_mm[i]);
    EXPECT_LT(((r->points.xyz_mm[i] - in.xyz_mm[i]) - 1e-3 * d_um * in.normal[i]).norm(), 1e-12);
    sum += d_um;
    sum2 += d_um * d_um;
  }
  const double mean = sum / in.size(), sd = std::sqrt(sum2 / in.size() - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.1);
  EXPECT_NEAR(sd, 2.0, 0.06);
  EXPECT_EQ(r->points.feature, in.feature);
}

TEST(VirtualCmm, ProbeRadiusErrorShiftsOutward) {
  const PointSet in = Cylinder(100, 50.0);
  VirtualCmmOptions o;
  o.probe_radius_error_um = 1.5;
  std::mt19937_64 rng(42);
  Result<VirtualCmmResult> r = MeasureWithVirtualCmm(in, o, rng);
  ASSERT_TRUE(r.ok());
  for (size_t i = 0; i < in.size(); ++i) {
    EXPECT_NEAR(r->points.xyz_mm[i].head<2>().norm(), 50.0015, 1e-12);
  }
}

TEST(VirtualCmmTest, RandomPlacementIsReturnedAndDeterministic) {
  const PointSet in = Cylinder(50, 80.0);
  VirtualCmmOptions o;
  o.random_placement = true;
  std::mt19937_64 a(43), b(43);
  Result<VirtualCmmResult> ra = MeasureWithVirtualCmm(in, o, a);
  Result<VirtualCmmResult> rb = MeasureWithVirtualCmm(in, o, b);
  ASSERT_TRUE(ra.ok() && rb.ok());
  EXPECT_TRUE(ra->cmm_from_part.isApprox(rb->cmm_from_part, 0.0));
  EXPECT_GT(ra->cmm_from_part.translation().norm(), 1.0);  // not the identity
  EXPECT_LT((ra->cmm_from_part.linear().transpose() * ra->cmm_from_part.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  for (size_t i = 0; i < in.size(); ++i) {
    EXPECT_LT((ra->cmm_from_part.inverse() * ra->points.xyz_mm[i] - in.xyz_mm[i]).norm(), 1e-9);
    EXPECT_LT((ra->cmm_from_part.linear() * in.normal[i] - ra->points.normal[i]).norm(), 1e-12);
  }
}

TEST(VirtualCmm, RejectsMissingNormalsAndBadOptions) {
  PointSet in = Cylinder(10, 10.0);
  in.normal.clear();
  std::mt19937_64 rng(44);
  EXPECT_FALSE(MeasureWithVirtualCmm(in, {}, rng).ok());
  VirtualCmmOptions o;
  o.noise_sigma_um = -1;
  EXPECT_FALSE(MeasureWithVirtualCmm(Cylinder(10, 10.0), o, rng).ok());
}

}  // namespace
}  // namespace tpcal::kinematics
