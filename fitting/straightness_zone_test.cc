// Minimum-zone straightness in a plane (strip) and in space (cylinder about a line).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

#include "core/units.h"
#include "fitting/line_fit.h"
#include "fitting/minimum_zone.h"

namespace tpcal::fitting {
namespace {

// Brute force 2D: the narrowest strip is flush with a line through two of the points.
double BruteForceStrip(const std::vector<Eigen::Vector2d>& p) {
  long double best = 1e300L;
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      const long double ex = (long double)p[j].x() - p[i].x(), ey = (long double)p[j].y() - p[i].y();
      const long double len = std::sqrt(ex * ex + ey * ey);
      if (len == 0) continue;
      long double hi = -1e300L, lo = 1e300L;
      for (const auto& q : p) {
        const long double s = (ex * ((long double)q.y() - p[i].y()) - ey * ((long double)q.x() - p[i].x())) / len;
        hi = std::max(hi, s);
        lo = std::min(lo, s);
      }
      best = std::min(best, hi - lo);
    }
  }
  return static_cast<double>(best);
}

constexpr double kStraightnessRelTol = 1e-9;  // exact data; the width is a rounded square root

// The orthogonal least-squares line is the principal axis through the centroid (closed form).
template <int D>
std::pair<Eigen::Matrix<double, D, 1>, Eigen::Matrix<double, D, 1>> LeastSquaresLine(
    const std::vector<Eigen::Matrix<double, D, 1>>& p) {
  Eigen::Matrix<double, D, 1> c = Eigen::Matrix<double, D, 1>::Zero();
  for (const auto& x : p) c += x;
  c /= static_cast<double>(p.size());
  Eigen::Matrix<double, D, D> cov = Eigen::Matrix<double, D, D>::Zero();
  for (const auto& x : p) cov += (x - c) * (x - c).transpose();
  return {c, Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, D, D>>(cov).eigenvectors().col(D - 1)};
}

TEST(MinimumZoneStraightness2, MatchesBruteForce) {
  double worst = 0;
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> x(0, 100), e(-0.01, 0.01);
    std::vector<Eigen::Vector2d> p;
    const int n = 3 + static_cast<int>(seed % 20);
    for (int i = 0; i < n; ++i) {
      const double t = x(rng);
      p.emplace_back(t, 0.002 * t + e(rng));
    }
    const auto mz = MinimumZoneStraightness2(p);
    ASSERT_TRUE(mz.ok()) << mz.status().ToString();
    const double bf = BruteForceStrip(p);
    EXPECT_NEAR(mz->width_mm, bf, kStraightnessRelTol * bf + 1e-15) << "seed " << seed;
    worst = std::max(worst, std::abs(mz->width_mm - bf) / bf);
    EXPECT_TRUE(mz->certificate.verified_optimal);
    ASSERT_GE(mz->certificate.contacts.size(), 3u);
    const Eigen::Vector2d left(-mz->line.direction.y(), mz->line.direction.x());
    for (const ZoneContact& c : mz->certificate.contacts) {
      const double s = left.dot(p[c.index] - mz->line.point_mm);
      EXPECT_NEAR(s, (c.side == ZoneSide::kUpper ? 0.5 : -0.5) * mz->width_mm, 1e-12) << "seed " << seed;
    }
    // Not wider than the form about the least-squares line.
    const auto [c, d] = LeastSquaresLine<2>(p);
    double hi = -1e300, lo = 1e300;
    for (const auto& x : p) {
      const double s = d.x() * (x.y() - c.y()) - d.y() * (x.x() - c.x());
      hi = std::max(hi, s);
      lo = std::min(lo, s);
    }
    EXPECT_LE(mz->width_mm, hi - lo + 1e-15);
    const auto ls = FitLine2(p);  // the library's least-squares line
    ASSERT_TRUE(ls.ok()) << ls.status().ToString();
    EXPECT_LE(mz->width_mm, ls->stats.form_mm + 1e-15);
  }
  RecordProperty("worst_relative_deviation_from_brute_force", ::testing::PrintToString(worst));
}

TEST(MinimumZoneStraightness2, KnownStripAndInvariance) {
  // Points on y = 0 and y = 0.004 (exact) plus interior: width 0.004.
  std::vector<Eigen::Vector2d> p;
  for (int i = 0; i <= 20; ++i) p.emplace_back(5.0 * i, i % 2 ? 0.004 : (i % 4 ? 0.001 : 0.0));
  const auto mz = MinimumZoneStraightness2(p);
  ASSERT_TRUE(mz.ok());
  EXPECT_DOUBLE_EQ(mz->width_mm, 0.004);
  EXPECT_GT(mz->line.direction.x(), 0);  // along last - first
  const Eigen::Rotation2Dd rot(2.0);
  std::vector<Eigen::Vector2d> q;
  for (const auto& x : p) q.push_back(rot * x + Eigen::Vector2d(1000, 1000));
  std::mt19937_64 rng(1);
  std::shuffle(q.begin() + 1, q.end() - 1, rng);
  const auto moved = MinimumZoneStraightness2(q);
  ASSERT_TRUE(moved.ok());
  EXPECT_NEAR(moved->width_mm, 0.004, 1e-12);  // rounding of the moved points at 1000 mm
}

TEST(MinimumZoneStraightness2, Degenerate) {
  EXPECT_EQ(MinimumZoneStraightness2(std::vector<Eigen::Vector2d>{{1, 1}}).status().code(), StatusCode::kTooFewPoints);
  EXPECT_EQ(MinimumZoneStraightness2(std::vector<Eigen::Vector2d>{{1, 1}, {1, 1}}).status().code(),
            StatusCode::kDegenerate);
  const auto collinear = MinimumZoneStraightness2(std::vector<Eigen::Vector2d>{{0, 0}, {1, 2}, {3, 6}});
  ASSERT_TRUE(collinear.ok());
  EXPECT_EQ(collinear->width_mm, 0.0);
}

// Points around a line along `dir` through `c`, radial noise up to `radius`.
std::vector<Eigen::Vector3d> NoisyLine(std::mt19937_64& rng, int n, const Eigen::Vector3d& c, const Eigen::Vector3d& dir,
                                       double length, double radius) {
  const Eigen::Vector3d u = dir.normalized();
  Eigen::Vector3d e1 = u.unitOrthogonal(), e2 = u.cross(e1);
  std::uniform_real_distribution<double> t(-length / 2, length / 2), a(0, 2 * kPi), r(0, 1);
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i < n; ++i) {
    const double ang = a(rng), rr = radius * std::sqrt(r(rng));
    p.push_back(c + t(rng) * u + rr * (std::cos(ang) * e1 + std::sin(ang) * e2));
  }
  return p;
}

// Diameter of the smallest cylinder with axis direction d containing p (exact MCC of the projection).
double DiameterAlong(const std::vector<Eigen::Vector3d>& p, const Eigen::Vector3d& d) {
  const Eigen::Vector3d u = d.normalized(), e1 = u.unitOrthogonal(), e2 = u.cross(e1);
  std::vector<Eigen::Vector2d> q;
  for (const auto& x : p) q.emplace_back(e1.dot(x), e2.dot(x));
  return 2 * MinimumCircumscribedCircle(q)->circle.radius_mm;
}

TEST(MinimumZoneStraightness3, NoDirectionDoesBetterAndCertificateHolds) {
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    std::mt19937_64 rng(seed);
    const auto p = NoisyLine(rng, 30 + 10 * seed, {10, -20, 5}, {1, 2, 0.5}, 120, 0.005);
    const auto mz = MinimumZoneStraightness3(p);
    ASSERT_TRUE(mz.ok()) << mz.status().ToString();
    EXPECT_TRUE(mz->certificate.verified_optimal) << mz->certificate.message;
    EXPECT_EQ(mz->certificate.scope, OptimalityScope::kGlobal);
    // Reported diameter is the zone about the reported axis.
    double dmax = 0;
    for (const auto& x : p) dmax = std::max(dmax, Distance(mz->axis, x));
    EXPECT_NEAR(mz->diameter_mm, 2 * dmax, 1e-12);
    // Search over directions about the reported axis (exact MCC per direction): none is narrower.
    const Eigen::Vector3d u = mz->axis.direction, e1 = u.unitOrthogonal(), e2 = u.cross(e1);
    const double span = 4 * mz->diameter_mm / 120;
    std::uniform_real_distribution<double> tilt(-span, span);
    double best_probe = DiameterAlong(p, u);
    EXPECT_NEAR(best_probe, mz->diameter_mm, 1e-9 * mz->diameter_mm);
    for (int k = 0; k < 300; ++k) {
      const double t1 = tilt(rng), t2 = tilt(rng);  // drawn in this order under every compiler
      const double probe = DiameterAlong(p, u + t1 * e1 + t2 * e2);
      EXPECT_GE(probe, mz->diameter_mm - mz->certificate.optimality_gap_mm) << "seed " << seed;
      best_probe = std::min(best_probe, probe);
    }
    // Not wider than the zone about the least-squares line.
    const auto [c, d] = LeastSquaresLine<3>(p);
    double ls_max = 0;
    for (const auto& x : p) ls_max = std::max(ls_max, (x - c).cross(d).norm());
    EXPECT_LE(mz->diameter_mm, 2 * ls_max + 1e-12);
    const auto ls = FitLine3(p);  // the library's least-squares line
    ASSERT_TRUE(ls.ok()) << ls.status().ToString();
    double fit_max = 0;
    for (const auto& x : p) fit_max = std::max(fit_max, Distance(ls->feature, x));
    EXPECT_LE(mz->diameter_mm, 2 * fit_max + 1e-12);
  }
}

TEST(MinimumZoneStraightness3, KnownCylinderAndFarOrigin) {
  // Points exactly on a cylinder of radius 0.003 about the z axis at both ends and mid-length
  // (3 around at each end), plus interior points: the zone diameter is 0.006.
  std::vector<Eigen::Vector3d> p;
  const double r = 0.003;
  for (double z : {0.0, 50.0, 100.0}) {
    for (int k = 0; k < 3; ++k) {
      const double a = 2 * kPi * k / 3 + z;
      p.emplace_back(r * std::cos(a), r * std::sin(a), z);
    }
  }
  for (int i = 1; i < 20; ++i) p.emplace_back(0.001 * std::cos(i), 0.001 * std::sin(i), 5.0 * i);
  const auto mz = MinimumZoneStraightness3(p);
  ASSERT_TRUE(mz.ok()) << mz.status().ToString();
  EXPECT_NEAR(mz->diameter_mm, 2 * r, 1e-12);
  EXPECT_TRUE(mz->certificate.verified_optimal) << mz->certificate.message;
  // Rigid motion to 1000 mm and reordering.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.8, Eigen::Vector3d(1, -1, 2).normalized()).toRotationMatrix();
  std::vector<Eigen::Vector3d> q;
  for (const auto& x : p) q.push_back(R * x + Eigen::Vector3d(1000, 1000, -1000));
  std::mt19937_64 rng(4);
  std::shuffle(q.begin(), q.end(), rng);
  const auto moved = MinimumZoneStraightness3(q);
  ASSERT_TRUE(moved.ok());
  EXPECT_NEAR(moved->diameter_mm, mz->diameter_mm, 1e-11);
  EXPECT_TRUE(SameDirection(moved->axis.direction, R * mz->axis.direction, 1e-9));
}

TEST(MinimumZoneStraightness3, Degenerate) {
  EXPECT_EQ(MinimumZoneStraightness3(std::vector<Eigen::Vector3d>{{0, 0, 0}, {1, 0, 0}}).status().code(),
            StatusCode::kTooFewPoints);
  EXPECT_EQ(MinimumZoneStraightness3(std::vector<Eigen::Vector3d>(5, Eigen::Vector3d(1, 2, 3))).status().code(),
            StatusCode::kDegenerate);
  // A blob (octahedron), not a line: no enclosing cylinder is longer than it is wide.
  std::vector<Eigen::Vector3d> blob{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  EXPECT_EQ(MinimumZoneStraightness3(blob).status().code(), StatusCode::kDegenerate);
}

}  // namespace
}  // namespace tpcal::fitting
