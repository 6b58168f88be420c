// Minimum-zone flatness against brute force, CGAL Width_3 truths, constructed slabs, invariances.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

#include "fitting/minimum_zone.h"
#include "fitting/minimum_zone_exact.h"
#include "fitting/plane_fit.h"

namespace tpcal::fitting {
namespace {

// Brute force: the narrowest slab is supported by a face (3 points) and a vertex, or by two
// edges (2 + 2 points): take every such direction, evaluate the directional width, keep the least.
double BruteForceFlatness(const std::vector<Eigen::Vector3d>& p) {
  using V = Eigen::Matrix<long double, 3, 1>;
  const std::size_t n = p.size();
  std::vector<V> q;
  for (const auto& x : p) q.push_back(x.cast<long double>());
  auto width_along = [&](const V& d) {
    const long double len = d.norm();
    if (len == 0) return static_cast<long double>(1e300);
    long double hi = -1e300L, lo = 1e300L;
    for (const auto& x : q) {
      const long double s = d.dot(x) / len;
      hi = std::max(hi, s);
      lo = std::min(lo, s);
    }
    return hi - lo;
  };
  long double best = 1e300L;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      for (std::size_t k = j + 1; k < n; ++k) best = std::min(best, width_along((q[j] - q[i]).cross(q[k] - q[i])));
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      for (std::size_t k = 0; k < n; ++k)
        for (std::size_t l = k + 1; l < n; ++l) best = std::min(best, width_along((q[j] - q[i]).cross(q[l] - q[k])));
  return static_cast<double>(best);
}

std::vector<Eigen::Vector3d> NoisyPlane(std::mt19937_64& rng, int n, double noise) {
  std::uniform_real_distribution<double> u(-50, 50), e(-noise, noise);
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i < n; ++i) {
    const double x = u(rng), y = u(rng);
    p.emplace_back(x, y, 1e-4 * x - 2e-4 * y + e(rng));
  }
  return p;
}

// Exact data; the reported width is the square root of an exact rational, rounded.
constexpr double kFlatnessRelTol = 1e-9;

double FormAbout(const std::vector<Eigen::Vector3d>& p, const Eigen::Vector3d& n) {
  double hi = -1e300, lo = 1e300;
  for (const auto& x : p) {
    hi = std::max(hi, n.dot(x));
    lo = std::min(lo, n.dot(x));
  }
  return hi - lo;
}

TEST(MinimumZoneFlatness, MatchesBruteForceOnRandomSets) {
  double worst = 0;
  for (std::uint64_t seed = 1; seed <= 25; ++seed) {
    std::mt19937_64 rng(seed);
    const int n = 5 + static_cast<int>(seed % 8);
    auto p = seed % 2 ? NoisyPlane(rng, n, 0.01) : std::vector<Eigen::Vector3d>{};
    if (p.empty()) {  // fully 3D random sets too
      std::uniform_real_distribution<double> u(-1, 1);
      for (int i = 0; i < n; ++i) p.push_back(Eigen::Vector3d{u(rng), u(rng), u(rng)});
    }
    const auto mz = MinimumZoneFlatness(p);
    ASSERT_TRUE(mz.ok()) << mz.status().ToString();
    const double bf = BruteForceFlatness(p);
    EXPECT_NEAR(mz->width_mm, bf, kFlatnessRelTol * bf) << "seed " << seed;
    worst = std::max(worst, std::abs(mz->width_mm - bf) / bf);
    EXPECT_TRUE(mz->certificate.verified_optimal);
    EXPECT_TRUE(mz->certificate.exact);
    EXPECT_EQ(mz->certificate.scope, OptimalityScope::kGlobal);
    // The contacts define the zone: at least 4 points (3 + 1 or 2 + 2), each on its plane.
    ASSERT_GE(mz->certificate.contacts.size(), 4u);
    for (const ZoneContact& c : mz->certificate.contacts) {
      const double s = mz->plane.SignedDistance(p[c.index]);
      EXPECT_NEAR(s, (c.side == ZoneSide::kUpper ? 0.5 : -0.5) * mz->width_mm, 1e-12) << "seed " << seed;
    }
    // The zone contains all points.
    for (const auto& x : p) EXPECT_LE(std::abs(mz->plane.SignedDistance(x)), 0.5 * mz->width_mm + 1e-12);
  }
  RecordProperty("worst_relative_deviation_from_brute_force", ::testing::PrintToString(worst));
}

TEST(MinimumZoneFlatness, EqualsWidth3OnAllPoints) {
  // The exact reference: CGAL Width_3 on every point. Both are exact: the doubles must agree to
  // the rounding of the final square root.
  for (std::uint64_t seed = 40; seed < 44; ++seed) {
    std::mt19937_64 rng(seed);
    auto p = NoisyPlane(rng, 600, 0.002);
    if (seed % 2) {  // a wavy face
      for (auto& x : p) x.z() += 0.001 * std::sin(x.x() / 7.0);
    }
    const auto mz = MinimumZoneFlatness(p);
    const auto ref = internal::FlatnessWidth3AllPoints(p);
    ASSERT_TRUE(mz.ok() && ref.ok());
    EXPECT_NEAR(mz->width_mm, *ref, 4e-16 * *ref) << "seed " << seed << " " << mz->certificate.message;
    // The exact-hull fallback (forced) gives the same exact answer.
    const auto hull = internal::MinimumZoneFlatnessWithSubsetLimit(p, {}, std::nullopt, 0);
    ASSERT_TRUE(hull.ok());
    EXPECT_NEAR(hull->width_mm, *ref, 4e-16 * *ref) << "seed " << seed;
    EXPECT_NE(hull->certificate.method.find("convex hull"), std::string::npos) << hull->certificate.message;
  }
}

TEST(MinimumZoneFlatness, PointsBetweenTwoKnownPlanes) {
  // Points on z = 0 and z = 0.025 (exactly representable) plus interior points: width 0.025.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-40, 40), t(0.001, 0.024);
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i < 30; ++i) {
    p.push_back(Eigen::Vector3d{u(rng), u(rng), i % 3 == 0 ? 0.0 : (i % 3 == 1 ? 0.025 : t(rng))});
  }
  const auto mz = MinimumZoneFlatness(p);
  ASSERT_TRUE(mz.ok());
  EXPECT_DOUBLE_EQ(mz->width_mm, 0.025);
  EXPECT_NEAR(std::abs(mz->plane.normal.z()), 1.0, 1e-15);
  EXPECT_EQ(mz->certificate.contacts.size(), 20u);  // every point on z = 0 or z = 0.025
}

TEST(MinimumZoneFlatness, LargeSetIsExactAndNotWiderThanLeastSquaresForm) {
  std::mt19937_64 rng(9);
  const auto p = NoisyPlane(rng, 20000, 0.003);
  const auto mz = MinimumZoneFlatness(p);
  ASSERT_TRUE(mz.ok());
  // The minimum zone is never wider than the form about the least-squares plane.
  const auto ls = FitPlane(p);
  ASSERT_TRUE(ls.ok()) << ls.status().ToString();
  EXPECT_LE(mz->width_mm, ls->stats.form_mm + 1e-15);
  EXPECT_LE(mz->width_mm, FormAbout(p, ls->feature.normal) + 1e-15);
  EXPECT_NEAR(mz->width_mm, FormAbout(p, mz->plane.normal), 1e-12);
  EXPECT_TRUE(mz->certificate.verified_optimal);
}

TEST(MinimumZoneFlatness, InvariantUnderRigidMotionOrderAndFarOrigin) {
  std::mt19937_64 rng(21);
  const auto p = NoisyPlane(rng, 3000, 0.002);
  const auto base = MinimumZoneFlatness(p);
  ASSERT_TRUE(base.ok());
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()) *
                             Eigen::AngleAxisd(-1.1, Eigen::Vector3d::UnitZ())).toRotationMatrix();
  const Eigen::Vector3d t(1000, -1000, 1000);
  std::vector<Eigen::Vector3d> q;
  for (const auto& x : p) q.push_back(R * x + t);
  std::shuffle(q.begin(), q.end(), rng);
  const auto moved = MinimumZoneFlatness(q);
  ASSERT_TRUE(moved.ok());
  // The moved points are rounded (~1e-13 mm at 1000 mm): that is the only difference.
  EXPECT_NEAR(moved->width_mm, base->width_mm, 1e-11);
  EXPECT_NEAR(std::abs(moved->plane.normal.dot(R * base->plane.normal)), 1.0, 1e-9);
}

TEST(MinimumZoneFlatness, DegenerateInputs) {
  std::vector<Eigen::Vector3d> two{{0, 0, 0}, {1, 0, 0}};
  EXPECT_EQ(MinimumZoneFlatness(two).status().code(), StatusCode::kTooFewPoints);
  std::vector<Eigen::Vector3d> line{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {-3, -3, -3}};
  EXPECT_EQ(MinimumZoneFlatness(line).status().code(), StatusCode::kDegenerate);
  std::vector<Eigen::Vector3d> flat{{0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {3, 5, 1}};
  const auto z = MinimumZoneFlatness(flat);
  ASSERT_TRUE(z.ok());
  EXPECT_EQ(z->width_mm, 0.0);
  EXPECT_EQ(z->plane.normal, Eigen::Vector3d(0, 0, 1));
  std::vector<Eigen::Vector3d> nan{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, std::nan("")}};
  EXPECT_EQ(MinimumZoneFlatness(nan).status().code(), StatusCode::kInvalidArgument);
}

TEST(MinimumZoneFlatness, NormalFollowsHint) {
  std::mt19937_64 rng(5);
  const auto p = NoisyPlane(rng, 50, 0.01);
  const auto up = MinimumZoneFlatness(p, {}, Eigen::Vector3d(0, 0, -1));
  ASSERT_TRUE(up.ok());
  EXPECT_LT(up->plane.normal.z(), 0);
  for (const ZoneContact& c : up->certificate.contacts) {
    EXPECT_NEAR(up->plane.SignedDistance(p[c.index]), (c.side == ZoneSide::kUpper ? 0.5 : -0.5) * up->width_mm, 1e-12);
  }
}

}  // namespace
}  // namespace tpcal::fitting
