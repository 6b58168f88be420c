// Minimum-zone flatness (ISO 12781 MZPL): the width of the point set, exact.
//
// CGAL Width_3 is exact (homogeneous GMP integers) but slow on large sets (it builds the exact hull
// and enumerates antipodal pairs without filtering: ~3 s for 1e5 points). The width is monotone
// under inclusion, so it is computed on a small subset S and verified on all points:
//   1. S = the points most extreme along the principal (PCA) normal, plus 4 affinely independent
//      points;
//   2. Width_3(S) gives the two exact planes of the narrowest slab containing S;
//   3. every point is tested against the slab in exact arithmetic (interval filter, GMP fallback);
//      if all lie inside, width(all) <= width(S) <= width(all): the answer is exact. Otherwise the
//      worst violators join S and step 2 repeats (S only grows: it terminates).
// If S grows large, the exact convex hull (CGAL extreme_points_3, exact predicates) replaces it.
// This is the only fitting/ translation unit with CGAL 3D kernels.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Extreme_points_traits_adapter_3.h>
#include <CGAL/Gmpq.h>
#include <CGAL/Gmpz.h>
#include <CGAL/Homogeneous.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/Width_3.h>
#include <CGAL/Width_default_traits_3.h>
#include <CGAL/convex_hull_3.h>
#include <CGAL/property_map.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>

#include "fitting/minimum_zone.h"
#include "fitting/minimum_zone_exact.h"
#include "fitting/minimum_zone_lp.h"

namespace tpcal::fitting {
namespace {

using FlatnessK = CGAL::Epick;
using HK = CGAL::Homogeneous<CGAL::Gmpz>;
using WidthTraits = CGAL::Width_default_traits_3<HK>;
using Z = CGAL::Gmpz;
using FlatnessI = CGAL::Interval_nt_advanced;  // needs CGAL::Protect_FPU_rounding in scope

// Exact integer coordinates: x = X / 2^shift for every coordinate of every point.
class IntegerCoordinates {
 public:
  static Result<IntegerCoordinates> Make(std::span<const Eigen::Vector3d> pts) {
    int shift = 0, max_exp = std::numeric_limits<int>::min();
    for (const auto& p : pts) {
      for (int j = 0; j < 3; ++j) {
        if (p[j] == 0) continue;
        int e = 0;
        std::frexp(p[j], &e);  // |x| = m 2^e, m in [0.5, 1): x 2^(53 - e) is an integer
        shift = std::max(shift, 53 - e);
        max_exp = std::max(max_exp, e);
      }
    }
    if (max_exp != std::numeric_limits<int>::min() && shift + max_exp > 1000) {
      return Status(StatusCode::kInvalidArgument,
                    "coordinates span too many orders of magnitude for exact flatness (> 1e300)");
    }
    IntegerCoordinates out;
    out.shift_ = shift;
    mpz_t w;
    mpz_init(w);
    mpz_ui_pow_ui(w, 2, static_cast<unsigned long>(shift));
    out.w_ = Z(w);
    mpz_clear(w);
    return out;
  }
  Z Int(double x) const {
    mpz_t z;
    mpz_init(z);
    mpz_set_d(z, std::ldexp(x, shift_));  // exact: an integer below 2^1000
    Z out(z);
    mpz_clear(z);
    return out;
  }
  HK::Point_3 Point(const Eigen::Vector3d& p) const { return HK::Point_3(Int(p.x()), Int(p.y()), Int(p.z()), w_); }
  const Z& w() const { return w_; }
  int shift() const { return shift_; }

 private:
  int shift_ = 0;
  Z w_;
};

// The slab a.x in [lo, hi] (a = (A, B, C) integers; lo, hi = -D/w, -K/w sorted) and the exact test.
struct Slab {
  Z A, B, C, D_lo, D_hi;  // planes A X + B Y + C Z + D W = 0 (D_lo gives the lower value of a.x)
  Z M;                    // max(|A|, |B|, |C|); the intervals below are divided by it
  FlatnessI ai, bi, ci, lo_i, hi_i;
};

enum class SlabSide { kInside, kOnLower, kOnUpper, kBelow, kAbove };

SlabSide Classify(const Slab& s, const IntegerCoordinates& ic, const Eigen::Vector3d& p, double* excess) {
  {
    CGAL::Protect_FPU_rounding<true> guard;
    const FlatnessI v = s.ai * p.x() + s.bi * p.y() + s.ci * p.z();
    if (v.inf() > s.lo_i.sup() && v.sup() < s.hi_i.inf()) return SlabSide::kInside;
    if (v.sup() < s.lo_i.inf()) {
      *excess = CGAL::to_double(s.lo_i) - CGAL::to_double(v);
      return SlabSide::kBelow;
    }
    if (v.inf() > s.hi_i.sup()) {
      *excess = CGAL::to_double(v) - CGAL::to_double(s.hi_i);
      return SlabSide::kAbove;
    }
  }
  // Exact: A X + B Y + C Z + D W with X = x 2^shift.
  const Z axyz = s.A * ic.Int(p.x()) + s.B * ic.Int(p.y()) + s.C * ic.Int(p.z());
  const int sl = CGAL::sign(axyz + s.D_lo * ic.w());
  const int sh = CGAL::sign(axyz + s.D_hi * ic.w());
  *excess = 0;
  if (sl < 0) return SlabSide::kBelow;
  if (sh > 0) return SlabSide::kAbove;
  if (sl == 0) return SlabSide::kOnLower;
  if (sh == 0) return SlabSide::kOnUpper;
  return SlabSide::kInside;
}

struct WidthOnSubset {
  Slab slab;
  Z width_num, width_den;  // squared width = num / den
};

WidthOnSubset RunWidth3(std::span<const Eigen::Vector3d> pts, const std::vector<std::size_t>& subset,
                        const IntegerCoordinates& ic) {
  std::vector<HK::Point_3> hp;
  hp.reserve(subset.size());
  for (std::size_t i : subset) hp.push_back(ic.Point(pts[i]));
  CGAL::Width_3<WidthTraits> width(hp.begin(), hp.end());
  Z a, b, c, d, k;
  width.get_width_coefficients(a, b, c, d, k);
  WidthOnSubset out;
  width.get_squared_width(out.width_num, out.width_den);
  out.slab.A = a;
  out.slab.B = b;
  out.slab.C = c;
  // a.x = -d/w on one plane and -k/w on the other (Cartesian x = X / w with the common w).
  // Sort so that D_lo gives the smaller value of a.x, i.e. the larger D.
  if (d > k) {
    out.slab.D_lo = d;
    out.slab.D_hi = k;
  } else {
    out.slab.D_lo = k;
    out.slab.D_hi = d;
  }
  // Width_3 plane coefficients refer to homogeneous points with the common w: A X + B Y + C Z + D W.
  // In Cartesian terms: a.x + D = 0 with x = X / W, so a.x = -D (no division by w).
  // Intervals of the coefficients scaled by M = max(|A|, |B|, |C|) (the raw integers may exceed
  // the double range).
  Slab& s = out.slab;
  Z M = CGAL::abs(s.A);
  if (CGAL::abs(s.B) > M) M = CGAL::abs(s.B);
  if (CGAL::abs(s.C) > M) M = CGAL::abs(s.C);
  auto scaled = [&M](const Z& z) { return FlatnessI(CGAL::to_interval(CGAL::Gmpq(z, M))); };
  s.M = M;
  s.ai = scaled(s.A);
  s.bi = scaled(s.B);
  s.ci = scaled(s.C);
  s.lo_i = -scaled(s.D_lo);
  s.hi_i = -scaled(s.D_hi);
  return out;
}

// Normal sign rule of FitPlane: along hint if given, else +z >= 0, then +y, then +x.
Eigen::Vector3d OrientNormal(Eigen::Vector3d n, const std::optional<Eigen::Vector3d>& hint) {
  double key = 0;
  if (hint && hint->dot(n) != 0) key = hint->dot(n);
  else if (n.z() != 0) key = n.z();
  else if (n.y() != 0) key = n.y();
  else key = n.x();
  return key < 0 ? Eigen::Vector3d(-n) : n;
}

}  // namespace

Result<double> internal::FlatnessWidth3AllPoints(std::span<const Eigen::Vector3d> points_mm) {
  if (points_mm.size() < 4) return Status(StatusCode::kTooFewPoints, "Width_3 reference needs at least 4 points");
  Result<IntegerCoordinates> ic = IntegerCoordinates::Make(points_mm);
  TPCAL_RETURN_IF_ERROR(ic);
  std::vector<HK::Point_3> hp;
  hp.reserve(points_mm.size());
  for (const auto& p : points_mm) hp.push_back(ic->Point(p));
  CGAL::Width_3<WidthTraits> width(hp.begin(), hp.end());
  Z num, den;
  width.get_squared_width(num, den);
  return std::sqrt(CGAL::to_double(CGAL::Gmpq(num, den)));
}

Result<FlatnessZone> MinimumZoneFlatness(std::span<const Eigen::Vector3d> points_mm, const ZoneOptions& options,
                                         std::optional<Eigen::Vector3d> normal_hint) {
  return internal::MinimumZoneFlatnessWithSubsetLimit(points_mm, options, normal_hint, 400);
}

Result<FlatnessZone> internal::MinimumZoneFlatnessWithSubsetLimit(std::span<const Eigen::Vector3d> points_mm,
                                                                  const ZoneOptions& options,
                                                                  std::optional<Eigen::Vector3d> normal_hint,
                                                                  std::size_t max_subset) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  const std::size_t n = points_mm.size();
  if (n < 3) {
    return Status(StatusCode::kTooFewPoints, "minimum-zone flatness needs at least 3 points, got " + std::to_string(n));
  }
  if (const long bad = internal::FirstNonFinite(points_mm); bad >= 0) {
    return Status(StatusCode::kInvalidArgument, "point " + std::to_string(bad) + " has a non-finite coordinate");
  }
  auto kp = [&](std::size_t i) { return FlatnessK::Point_3(points_mm[i].x(), points_mm[i].y(), points_mm[i].z()); };
  // Four affinely independent points, decided exactly.
  std::size_t i1 = 1;
  while (i1 < n && points_mm[i1] == points_mm[0]) ++i1;
  if (i1 == n) return Status(StatusCode::kDegenerate, "minimum-zone flatness: all points coincide");
  std::size_t i2 = 0;
  for (std::size_t i = 1; i < n && i2 == 0; ++i) {
    if (!CGAL::collinear(kp(0), kp(i1), kp(i))) i2 = i;
  }
  if (i2 == 0) return Status(StatusCode::kDegenerate, "minimum-zone flatness: the points are collinear");

  FlatnessZone out;
  out.n_points = n;
  ZoneCertificate& cert = out.certificate;
  cert.scope = OptimalityScope::kGlobal;
  cert.exact = true;
  cert.optimality_gap_mm = 0;
  cert.verified_optimal = true;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : points_mm) centroid += p;
  centroid /= static_cast<double>(n);

  std::size_t i3 = 0;
  for (std::size_t i = 1; i < n && i3 == 0; ++i) {
    if (CGAL::orientation(kp(0), kp(i1), kp(i2), kp(i)) != CGAL::COPLANAR) i3 = i;
  }
  if (i3 == 0) {  // exactly coplanar: width 0, every point touches both planes
    const Eigen::Vector3d nrm =
        OrientNormal((points_mm[i1] - points_mm[0]).cross(points_mm[i2] - points_mm[0]).normalized(), normal_hint);
    out.plane = Plane{centroid - nrm.dot(centroid - points_mm[0]) * nrm, nrm};
    out.width_mm = 0;
    for (std::size_t i = 0; i < n; ++i) {
      cert.contacts.push_back({i, ZoneSide::kLower});
      cert.contacts.push_back({i, ZoneSide::kUpper});
    }
    cert.method = "exact coplanarity test";
    cert.message = "exact: all points coplanar";
    return out;
  }

  Result<IntegerCoordinates> ic_or = IntegerCoordinates::Make(points_mm);
  TPCAL_RETURN_IF_ERROR(ic_or);
  const IntegerCoordinates& ic = *ic_or;

  // Principal normal (double): the direction of least spread.
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : points_mm) cov += (p - centroid) * (p - centroid).transpose();
  const Eigen::Vector3d n0 = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvectors().col(0);
  std::vector<double> h(n);
  for (std::size_t i = 0; i < n; ++i) h[i] = n0.dot(points_mm[i] - centroid);

  std::vector<std::size_t> subset{0, i1, i2, i3};
  auto add_unique = [&](std::size_t i) {
    if (std::find(subset.begin(), subset.end(), i) == subset.end()) subset.push_back(i);
  };
  {
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t{0});
    const std::size_t m = std::min<std::size_t>(8, n);
    std::partial_sort(order.begin(), order.begin() + m, order.end(), [&](auto a, auto b) { return h[a] > h[b]; });
    for (std::size_t i = 0; i < m; ++i) add_unique(order[i]);
    std::partial_sort(order.begin(), order.begin() + m, order.end(), [&](auto a, auto b) { return h[a] < h[b]; });
    for (std::size_t i = 0; i < m; ++i) add_unique(order[i]);
  }

  const std::size_t kMaxSubset = max_subset;
  constexpr int kPerRound = 8;
  WidthOnSubset w;
  int rounds = 0;
  bool used_hull = false;
  // Fallback: the exact convex hull (its width is the width of the set).
  auto use_hull = [&] {
    std::vector<FlatnessK::Point_3> P;
    P.reserve(n);
    for (const auto& p : points_mm) P.emplace_back(p.x(), p.y(), p.z());
    std::vector<std::size_t> idx(n);
    std::iota(idx.begin(), idx.end(), std::size_t{0});
    subset.clear();
    CGAL::extreme_points_3(idx, std::back_inserter(subset),
                           CGAL::make_extreme_points_traits_adapter(CGAL::make_property_map(P)));
    used_hull = true;
  };
  if (subset.size() > kMaxSubset) use_hull();
  std::vector<std::size_t> lower_contacts, upper_contacts;
  for (;;) {
    ++rounds;
    w = RunWidth3(points_mm, subset, ic);
    lower_contacts.clear();
    upper_contacts.clear();
    std::vector<std::pair<double, std::size_t>> below, above;
    for (std::size_t i = 0; i < n; ++i) {
      double excess = 0;
      switch (Classify(w.slab, ic, points_mm[i], &excess)) {
        case SlabSide::kInside: break;
        case SlabSide::kOnLower: lower_contacts.push_back(i); break;
        case SlabSide::kOnUpper: upper_contacts.push_back(i); break;
        case SlabSide::kBelow: below.emplace_back(excess, i); break;
        case SlabSide::kAbove: above.emplace_back(excess, i); break;
      }
    }
    if (below.empty() && above.empty()) break;
    if (used_hull) {
      return Status(StatusCode::kInternal, "minimum-zone flatness: Width_3 slab of the hull misses a point");
    }
    if (subset.size() > kMaxSubset) {
      use_hull();
      continue;
    }
    for (auto* v : {&below, &above}) {
      std::sort(v->begin(), v->end(), std::greater<>());
      for (std::size_t t = 0; t < v->size() && t < kPerRound; ++t) add_unique((*v)[t].second);
    }
  }

  // Report: unit normal, width, mid-plane through the foot of the centroid.
  auto ratio = [&](const Z& z) { return CGAL::to_double(CGAL::Gmpq(z, w.slab.M)); };
  const Eigen::Vector3d a(ratio(w.slab.A), ratio(w.slab.B), ratio(w.slab.C));
  const double a_norm = a.norm();
  const double lo = -ratio(w.slab.D_lo) / a_norm, hi = -ratio(w.slab.D_hi) / a_norm;
  Eigen::Vector3d nrm = a / a_norm;
  const Eigen::Vector3d oriented = OrientNormal(nrm, normal_hint);
  const bool flipped = oriented.dot(nrm) < 0;
  nrm = oriented;
  const double mid = flipped ? -0.5 * (lo + hi) : 0.5 * (lo + hi);
  out.plane = Plane{centroid - (nrm.dot(centroid) - mid) * nrm, nrm};
  out.width_mm = std::sqrt(CGAL::to_double(CGAL::Gmpq(w.width_num, w.width_den)));
  for (std::size_t i : lower_contacts) cert.contacts.push_back({i, flipped ? ZoneSide::kUpper : ZoneSide::kLower});
  for (std::size_t i : upper_contacts) cert.contacts.push_back({i, flipped ? ZoneSide::kLower : ZoneSide::kUpper});
  internal::NormalizeContacts(&cert.contacts);
  std::ostringstream method, msg;
  method << "exact Width_3 (homogeneous GMP integers) on " << (used_hull ? "the exact convex hull" : "an extreme subset")
         << ", verified on all points";
  msg << "exact: the narrowest slab of " << subset.size() << " points contains all " << n
      << " points (exact test), so it is the narrowest for all; " << rounds << " Width_3 round(s)";
  cert.method = method.str();
  cert.message = msg.str();
  return out;
}

}  // namespace tpcal::fitting
