// Minimum-zone circularity against brute force, constructed truths and invariances.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

#include "core/units.h"
#include "fitting/circle_fit.h"
#include "fitting/minimum_zone.h"

namespace tpcal::fitting {
namespace {

// Brute force: the optimum centre is a vertex of the overlay of the nearest- and farthest-point
// Voronoi diagrams: a circumcentre of 3 points, or the crossing of the bisectors of 2 pairs.
// Evaluate R - r at every such candidate (long double) and keep the least.
double BruteForceCircularity(const std::vector<Eigen::Vector2d>& p) {
  using LD = long double;
  const std::size_t n = p.size();
  auto zone = [&](LD cx, LD cy) {
    LD hi = 0, lo = 1e300L;
    for (const auto& q : p) {
      const LD r = std::sqrt((q.x() - cx) * (q.x() - cx) + (q.y() - cy) * (q.y() - cy));
      hi = std::max(hi, r);
      lo = std::min(lo, r);
    }
    return hi - lo;
  };
  LD best = 1e300L;
  // Bisector of (i, j): 2 (pj - pi) . c = |pj|^2 - |pi|^2.
  auto bis = [&](std::size_t i, std::size_t j, LD* a, LD* b, LD* c) {
    *a = 2 * (LD(p[j].x()) - p[i].x());
    *b = 2 * (LD(p[j].y()) - p[i].y());
    *c = (LD(p[j].x()) * p[j].x() + LD(p[j].y()) * p[j].y()) - (LD(p[i].x()) * p[i].x() + LD(p[i].y()) * p[i].y());
  };
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      LD a1, b1, c1;
      bis(i, j, &a1, &b1, &c1);
      for (std::size_t k = 0; k < n; ++k) {
        for (std::size_t l = k + 1; l < n; ++l) {
          if (k == i && l == j) continue;
          LD a2, b2, c2;
          bis(k, l, &a2, &b2, &c2);
          const LD det = a1 * b2 - a2 * b1;
          if (std::abs(det) < 1e-30L) continue;
          best = std::min(best, zone((c1 * b2 - c2 * b1) / det, (a1 * c2 - a2 * c1) / det));
        }
      }
    }
  }
  return static_cast<double>(best);
}

std::vector<Eigen::Vector2d> NoisyCircle(std::mt19937_64& rng, int n, const Eigen::Vector2d& c, double r,
                                         double noise, double arc_rad = 2 * kPi) {
  std::uniform_real_distribution<double> ang(0, arc_rad);
  std::uniform_real_distribution<double> dev(-noise, noise);
  std::vector<Eigen::Vector2d> p;
  for (int i = 0; i < n; ++i) {
    const double t = ang(rng);
    p.push_back(c + (r + dev(rng)) * Eigen::Vector2d(std::cos(t), std::sin(t)));
  }
  return p;
}

// Relative comparison for zone widths: exact data, double rounding of the reported value.
constexpr double kCircularityRelTol = 1e-9;

TEST(MinimumZoneCircularity, MatchesBruteForceOnRandomCircles) {
  double worst = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    std::mt19937_64 rng(seed);
    const int n = 6 + static_cast<int>(seed % 9);
    const auto p = NoisyCircle(rng, n, {3.0, -2.0}, 12.5, 0.05);
    const auto mz = MinimumZoneCircularity(p);
    ASSERT_TRUE(mz.ok()) << mz.status().ToString();
    const double bf = BruteForceCircularity(p);
    EXPECT_NEAR(mz->width_mm, bf, kCircularityRelTol * bf) << "seed " << seed;
    worst = std::max(worst, std::abs(mz->width_mm - bf) / bf);
    EXPECT_TRUE(mz->certificate.verified_optimal) << mz->certificate.message;
    EXPECT_EQ(mz->certificate.scope, OptimalityScope::kGlobal) << mz->certificate.message;
    EXPECT_TRUE(mz->certificate.exact);
    EXPECT_GE(mz->certificate.contacts.size(), 4u);
  }
  RecordProperty("worst_relative_deviation_from_brute_force", ::testing::PrintToString(worst));
}

TEST(MinimumZoneCircularity, GlobalCertificateIsNeverWrongOnScatteredPoints) {
  // Points that are not a circle: the certificate may decline, but when it says global it is right.
  int global = 0;
  for (std::uint64_t seed = 100; seed < 130; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-10, 10);
    std::vector<Eigen::Vector2d> p;
    for (int i = 0; i < 9; ++i) p.push_back(Eigen::Vector2d{u(rng), u(rng)});
    const auto mz = MinimumZoneCircularity(p);
    ASSERT_TRUE(mz.ok()) << mz.status().ToString();
    const double bf = BruteForceCircularity(p);
    EXPECT_GE(mz->width_mm, bf * (1 - kCircularityRelTol)) << "seed " << seed;  // never below the optimum
    if (mz->certificate.scope == OptimalityScope::kGlobal) {
      ++global;
      EXPECT_NEAR(mz->width_mm, bf, kCircularityRelTol * bf) << "seed " << seed << " " << mz->certificate.message;
    }
  }
  RecordProperty("global_certificates", global);
}

TEST(MinimumZoneCircularity, TwoConcentricCirclesGiveKnownWidth) {
  // 2k points alternately on R and r about (40, -25): the zone is exactly R - r.
  const Eigen::Vector2d c(40, -25);
  const double R = 30.0, r = 29.98;
  std::vector<Eigen::Vector2d> p;
  for (int i = 0; i < 16; ++i) {
    const double t = 2 * kPi * i / 16 + 0.1;
    p.push_back(c + (i % 2 ? r : R) * Eigen::Vector2d(std::cos(t), std::sin(t)));
  }
  // plus interior points between the circles
  for (int i = 0; i < 16; ++i) {
    const double t = 2 * kPi * i / 16 + 0.3;
    p.push_back(c + (r + 0.37 * (R - r)) * Eigen::Vector2d(std::cos(t), std::sin(t)));
  }
  const auto mz = MinimumZoneCircularity(p);
  ASSERT_TRUE(mz.ok()) << mz.status().ToString();
  // Truth R - r; the points carry rounding of ~1e-15 mm from cos/sin.
  EXPECT_NEAR(mz->width_mm, R - r, 1e-12);
  EXPECT_NEAR((mz->center_mm - c).norm(), 0, 1e-9);
  EXPECT_TRUE(mz->certificate.verified_optimal) << mz->certificate.message;
}

TEST(MinimumZoneCircularity, InvariantUnderRigidMotionOrderAndFarOrigin) {
  std::mt19937_64 rng(7);
  const auto p = NoisyCircle(rng, 200, {0, 0}, 25, 0.004);
  const auto base = MinimumZoneCircularity(p);
  ASSERT_TRUE(base.ok());
  const Eigen::Rotation2Dd rot(0.7);
  for (const Eigen::Vector2d& shift : {Eigen::Vector2d(1000, -1000), Eigen::Vector2d(-3.5, 12.0)}) {
    std::vector<Eigen::Vector2d> q;
    for (const auto& x : p) q.push_back(rot * x + shift);
    std::shuffle(q.begin(), q.end(), rng);
    const auto moved = MinimumZoneCircularity(q);
    ASSERT_TRUE(moved.ok());
    // Moving the points rounds them by ~1e-13 mm at 1000 mm.
    EXPECT_NEAR(moved->width_mm, base->width_mm, 1e-11);
    EXPECT_NEAR((moved->center_mm - (rot * base->center_mm + shift)).norm(), 0, 1e-8);
    EXPECT_TRUE(moved->certificate.verified_optimal) << moved->certificate.message;
  }
}

TEST(MinimumZoneCircularity, NotWiderThanZoneAboutOtherCentres) {
  std::mt19937_64 rng(11);
  const auto p = NoisyCircle(rng, 500, {5, 5}, 40, 0.01);
  const auto mz = MinimumZoneCircularity(p);
  ASSERT_TRUE(mz.ok());
  auto zone_about = [&](const Eigen::Vector2d& c) {
    double hi = 0, lo = 1e300;
    for (const auto& x : p) {
      hi = std::max(hi, (x - c).norm());
      lo = std::min(lo, (x - c).norm());
    }
    return hi - lo;
  };
  const auto ls = FitCircle2(p);
  ASSERT_TRUE(ls.ok()) << ls.status().ToString();
  EXPECT_LE(mz->width_mm, ls->stats.form_mm + 1e-12);
  EXPECT_LE(mz->width_mm, zone_about(ls->feature.center_mm) + 1e-12);
  const auto mcc = MinimumCircumscribedCircle(p);
  const auto mic = MaximumInscribedCircle(p);
  ASSERT_TRUE(mcc.ok() && mic.ok());
  EXPECT_LE(mz->width_mm, zone_about(mcc->circle.center_mm) + 1e-12);
  EXPECT_LE(mz->width_mm, zone_about(mic->circle.center_mm) + 1e-12);
  std::uniform_real_distribution<double> d(-0.01, 0.01);
  for (int i = 0; i < 200; ++i) {
    EXPECT_LE(mz->width_mm, zone_about(mz->center_mm + Eigen::Vector2d{d(rng), d(rng)}) + 1e-12);
  }
}

TEST(MinimumZoneCircularity, ShortArcIsHonest) {
  // A 20 degree arc: the zone is still found and certified at least locally; when the certificate
  // claims global scope it must match brute force.
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    std::mt19937_64 rng(seed);
    const auto p = NoisyCircle(rng, 12, {0, 0}, 30, 0.01, DegToRad(20));
    const auto mz = MinimumZoneCircularity(p);
    ASSERT_TRUE(mz.ok()) << mz.status().ToString();
    EXPECT_NE(mz->certificate.scope, OptimalityScope::kNotVerified) << mz->certificate.message;
    const double bf = BruteForceCircularity(p);
    EXPECT_GE(mz->width_mm, bf * (1 - kCircularityRelTol));
    if (mz->certificate.scope == OptimalityScope::kGlobal) {
      EXPECT_NEAR(mz->width_mm, bf, kCircularityRelTol * bf);
    }
  }
}

TEST(MinimumZoneCircularity, RejectsBadInput) {
  std::vector<Eigen::Vector2d> three{{0, 0}, {1, 0}, {0, 1}};
  EXPECT_EQ(MinimumZoneCircularity(three).status().code(), StatusCode::kTooFewPoints);
  std::vector<Eigen::Vector2d> line{{0, 0}, {1, 1}, {2, 2}, {3, 3}, {-4, -4}};
  EXPECT_EQ(MinimumZoneCircularity(line).status().code(), StatusCode::kDegenerate);
  std::vector<Eigen::Vector2d> nan{{0, 0}, {1, 0}, {0, 1}, {std::nan(""), 1}};
  EXPECT_EQ(MinimumZoneCircularity(nan).status().code(), StatusCode::kInvalidArgument);
  ZoneOptions bad;
  bad.max_iterations = 0;
  EXPECT_EQ(MinimumZoneCircularity(line, bad).status().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace tpcal::fitting
