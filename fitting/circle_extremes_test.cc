// Minimum circumscribed and maximum inscribed circles against brute force and constructed truths.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

#include "core/units.h"
#include "fitting/minimum_zone.h"

namespace tpcal::fitting {
namespace {

using LD = long double;
struct C {
  LD x, y, r;
};

bool Circumcircle(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c, C* out) {
  const LD bx = LD(b.x()) - a.x(), by = LD(b.y()) - a.y(), cx = LD(c.x()) - a.x(), cy = LD(c.y()) - a.y();
  const LD d = 2 * (bx * cy - by * cx);
  if (std::abs(d) < 1e-30L) return false;
  const LD nb = bx * bx + by * by, nc = cx * cx + cy * cy;
  const LD ux = (cy * nb - by * nc) / d, uy = (bx * nc - cx * nb) / d;
  *out = {a.x() + ux, a.y() + uy, std::sqrt(ux * ux + uy * uy)};
  return true;
}

LD Dist(const Eigen::Vector2d& p, LD x, LD y) { return std::hypot(LD(p.x()) - x, LD(p.y()) - y); }

// Brute force MCC: smallest circle through 2 (diametral) or 3 points containing all points.
double BruteForceMcc(const std::vector<Eigen::Vector2d>& p) {
  LD best = 1e300L;
  auto try_circle = [&](const C& c) {
    for (const auto& q : p) {
      if (Dist(q, c.x, c.y) > c.r * (1 + 1e-15L) + 1e-18L) return;
    }
    best = std::min(best, c.r);
  };
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      const LD mx = (LD(p[i].x()) + p[j].x()) / 2, my = (LD(p[i].y()) + p[j].y()) / 2;
      try_circle({mx, my, Dist(p[i], mx, my)});
      for (std::size_t k = j + 1; k < p.size(); ++k) {
        C c;
        if (Circumcircle(p[i], p[j], p[k], &c)) try_circle(c);
      }
    }
  }
  return static_cast<double>(best);
}

// Brute force MIC (largest empty circle with centre in the convex hull): candidates are the
// circumcentres of triples inside the hull and the crossings of pair bisectors with hull edges.
double BruteForceMic(const std::vector<Eigen::Vector2d>& p) {
  // Convex hull by brute force: edge (i, j) is a hull edge if all points are on its left or on it.
  std::vector<std::pair<std::size_t, std::size_t>> hull;
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::size_t j = 0; j < p.size(); ++j) {
      if (i == j) continue;
      bool ok = true;
      for (const auto& q : p) {
        const LD cr = (LD(p[j].x()) - p[i].x()) * (LD(q.y()) - p[i].y()) - (LD(p[j].y()) - p[i].y()) * (LD(q.x()) - p[i].x());
        if (cr < 0) ok = false;
      }
      if (ok) hull.emplace_back(i, j);
    }
  }
  auto inside = [&](LD x, LD y) {
    for (auto [i, j] : hull) {
      const LD cr = (LD(p[j].x()) - p[i].x()) * (y - p[i].y()) - (LD(p[j].y()) - p[i].y()) * (x - p[i].x());
      if (cr < -1e-12L) return false;
    }
    return true;
  };
  auto nearest = [&](LD x, LD y) {
    LD m = 1e300L;
    for (const auto& q : p) m = std::min(m, Dist(q, x, y));
    return m;
  };
  LD best = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j)
      for (std::size_t k = j + 1; k < p.size(); ++k) {
        C c;
        if (Circumcircle(p[i], p[j], p[k], &c) && inside(c.x, c.y)) best = std::max(best, nearest(c.x, c.y));
      }
  for (auto [a, b] : hull) {
    const LD ax = p[a].x(), ay = p[a].y(), dx = LD(p[b].x()) - ax, dy = LD(p[b].y()) - ay;
    for (std::size_t k = 0; k < p.size(); ++k)
      for (std::size_t l = k + 1; l < p.size(); ++l) {
        // 2 (l - k) . (a + t d) = |l|^2 - |k|^2
        const LD ex = LD(p[l].x()) - p[k].x(), ey = LD(p[l].y()) - p[k].y();
        const LD den = 2 * (ex * dx + ey * dy);
        if (std::abs(den) < 1e-30L) continue;
        const LD rhs = (LD(p[l].x()) * p[l].x() + LD(p[l].y()) * p[l].y()) - (LD(p[k].x()) * p[k].x() + LD(p[k].y()) * p[k].y());
        const LD t = (rhs - 2 * (ex * ax + ey * ay)) / den;
        if (t < 0 || t > 1) continue;
        best = std::max(best, nearest(ax + t * dx, ay + t * dy));
      }
  }
  return static_cast<double>(best);
}

constexpr double kExtremesRelTol = 1e-9;  // exact results, rounded; brute force in long double

TEST(ReferenceCircles, MatchBruteForce) {
  double worst = 0;
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    std::mt19937_64 rng(seed);
    std::vector<Eigen::Vector2d> p;
    const int n = 4 + static_cast<int>(seed % 10);
    if (seed % 2) {
      std::uniform_real_distribution<double> u(-10, 10);
      for (int i = 0; i < n; ++i) p.push_back(Eigen::Vector2d{u(rng), u(rng)});
    } else {
      std::uniform_real_distribution<double> a(0, 2 * kPi), e(-0.05, 0.05);
      for (int i = 0; i < n; ++i) {
        const double t = a(rng), r = 20 + e(rng);
        p.emplace_back(100 + r * std::cos(t), -50 + r * std::sin(t));
      }
    }
    const auto mcc = MinimumCircumscribedCircle(p);
    const auto mic = MaximumInscribedCircle(p);
    ASSERT_TRUE(mcc.ok() && mic.ok()) << mcc.status().ToString() << mic.status().ToString();
    const double bf_mcc = BruteForceMcc(p), bf_mic = BruteForceMic(p);
    EXPECT_NEAR(mcc->circle.radius_mm, bf_mcc, kExtremesRelTol * bf_mcc) << "seed " << seed;
    EXPECT_NEAR(mic->circle.radius_mm, bf_mic, kExtremesRelTol * bf_mic) << "seed " << seed;
    worst = std::max({worst, std::abs(mcc->circle.radius_mm - bf_mcc) / bf_mcc,
                      std::abs(mic->circle.radius_mm - bf_mic) / bf_mic});
    for (const auto* r : {&*mcc, &*mic}) {
      EXPECT_TRUE(r->certificate.verified_optimal);
      EXPECT_EQ(r->certificate.scope, OptimalityScope::kGlobal);
      ASSERT_GE(r->certificate.contacts.size(), 2u);
      for (const ZoneContact& c : r->certificate.contacts) {
        EXPECT_NEAR((p[c.index] - r->circle.center_mm).norm(), r->circle.radius_mm, 1e-12) << "seed " << seed;
      }
    }
    for (const auto& q : p) {
      EXPECT_LE((q - mcc->circle.center_mm).norm(), mcc->circle.radius_mm * (1 + 1e-15) + 1e-15);
      EXPECT_GE((q - mic->circle.center_mm).norm(), mic->circle.radius_mm * (1 - 1e-15) - 1e-15);
    }
  }
  RecordProperty("worst_relative_deviation_from_brute_force", ::testing::PrintToString(worst));
}

TEST(ReferenceCircles, KnownCirclesAndFarOrigin) {
  // A regular hexagon of radius 5 about (1000, -1000): MCC radius 5 and MIC (centre in the hull,
  // no point inside) radius 5, both about the hexagon's centre.
  std::vector<Eigen::Vector2d> p;
  for (int i = 0; i < 6; ++i) {
    const double t = kPi * i / 3;
    p.emplace_back(1000 + 5 * std::cos(t), -1000 + 5 * std::sin(t));
  }
  const auto mcc = MinimumCircumscribedCircle(p);
  const auto mic = MaximumInscribedCircle(p);
  ASSERT_TRUE(mcc.ok() && mic.ok());
  // Vertices carry cos/sin and translation rounding (~1e-13 mm at 1000 mm).
  EXPECT_NEAR(mcc->circle.radius_mm, 5, 1e-12);
  EXPECT_NEAR(mic->circle.radius_mm, 5, 1e-12);
  EXPECT_NEAR((mcc->circle.center_mm - Eigen::Vector2d(1000, -1000)).norm(), 0, 1e-12);
  EXPECT_NEAR(mcc->peak_to_valley_mm, 0, 1e-12);
}

TEST(ReferenceCircles, BadInput) {
  EXPECT_EQ(MinimumCircumscribedCircle(std::vector<Eigen::Vector2d>{{1, 2}}).status().code(), StatusCode::kTooFewPoints);
  EXPECT_EQ(MinimumCircumscribedCircle(std::vector<Eigen::Vector2d>{{1, 2}, {1, 2}}).status().code(),
            StatusCode::kDegenerate);
  EXPECT_EQ(MaximumInscribedCircle(std::vector<Eigen::Vector2d>{{0, 0}, {1, 1}, {2, 2}}).status().code(),
            StatusCode::kDegenerate);
  EXPECT_EQ(MaximumInscribedCircle(std::vector<Eigen::Vector2d>{{0, 0}, {1, 1}, {2, std::nan("")}}).status().code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace tpcal::fitting
