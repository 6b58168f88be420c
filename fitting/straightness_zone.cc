// Minimum-zone straightness: in a plane (strip, exact) and of a line in space (cylindrical zone).
//
// 2D: the minimum-width strip of the points is flush with an edge of their convex hull; exact
// rotating calipers on the exact hull (minimum_zone_exact2.cc).
//
// 3D (ISO 1101 straightness of a line in space with zone "diameter t"): minimise the largest
// distance of the points to a line. Sequential exact LP from the principal-axis line (see
// minimum_zone_axis.h). Global certificate, valid for every line in space: in the frame of the
// final axis u*, for a line L tilted by theta from u*,
//   (a) its true distances are >= cos(theta) x the distances measured in the planes z = const
//       ("slanted"), which are >= the LP model u_i . w_i(delta) (Cauchy-Schwarz); the LP minimum
//       over all delta (exact, interior to a huge box, so global by convexity) gives
//       D(L) >= 2 cos(theta) LP*;
//   (b) the two axially extreme points a, b project at least s sin(theta) - t apart (s: their
//       axial separation, t: their transverse one), so D(L) >= s sin(theta) - t.
// So D(L) >= min over theta of max((a), (b)) for every L: the gap to the reported diameter is a
// proven bound, about D (D/s)^2 (picometres for real straightness data).
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "fitting/minimum_zone.h"
#include "fitting/minimum_zone_axis.h"
#include "fitting/minimum_zone_exact.h"
#include "fitting/minimum_zone_lp.h"

namespace tpcal::fitting {
namespace {
constexpr double kStraightnessU = std::numeric_limits<double>::epsilon() / 2;
}  // namespace

Result<StraightnessZone2> MinimumZoneStraightness2(std::span<const Eigen::Vector2d> points_mm,
                                                   const ZoneOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  const std::size_t n = points_mm.size();
  if (n < 2) {
    return Status(StatusCode::kTooFewPoints, "minimum-zone straightness needs at least 2 points, got " + std::to_string(n));
  }
  if (const long bad = internal::FirstNonFinite(points_mm); bad >= 0) {
    return Status(StatusCode::kInvalidArgument, "point " + std::to_string(bad) + " has a non-finite coordinate");
  }
  internal::Strip2 strip = internal::MinimumWidthStrip2(points_mm);
  if (!strip.ok) return Status(StatusCode::kDegenerate, "minimum-zone straightness: " + strip.message);

  StraightnessZone2 out;
  out.n_points = n;
  out.width_mm = strip.width_mm;
  // Direction along the strip, sign as FitLine2: positive dot with (last - first point).
  Eigen::Vector2d dir(strip.normal.y(), -strip.normal.x());
  const Eigen::Vector2d span = points_mm[n - 1] - points_mm[0];
  if (dir.dot(span) < 0) dir = -dir;
  // kUpper is the left side of the direction: swap sides if the strip normal points right.
  const Eigen::Vector2d left(-dir.y(), dir.x());
  const bool swap = left.dot(strip.normal) < 0;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const auto& p : points_mm) centroid += p;
  centroid /= static_cast<double>(n);
  const double mid = strip.lower_offset_mm + 0.5 * strip.width_mm;  // along strip.normal
  out.line = Line2{centroid - (strip.normal.dot(centroid) - mid) * strip.normal, dir};
  ZoneCertificate& cert = out.certificate;
  for (ZoneContact c : strip.contacts) {
    if (swap) c.side = c.side == ZoneSide::kUpper ? ZoneSide::kLower : ZoneSide::kUpper;
    cert.contacts.push_back(c);
  }
  internal::NormalizeContacts(&cert.contacts);
  cert.scope = OptimalityScope::kGlobal;
  cert.exact = true;
  cert.verified_optimal = true;
  cert.optimality_gap_mm = 0;
  cert.method = "exact rotating calipers on the exact convex hull (rational widths)";
  cert.message = "exact: every hull edge's antipodal width compared in rationals; contacts lie exactly on the lines";
  return out;
}

Result<StraightnessZone3> MinimumZoneStraightness3(std::span<const Eigen::Vector3d> points_mm,
                                                   const ZoneOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  const std::size_t n = points_mm.size();
  if (n < 3) {
    return Status(StatusCode::kTooFewPoints, "3D straightness needs at least 3 points, got " + std::to_string(n));
  }
  if (const long bad = internal::FirstNonFinite(points_mm); bad >= 0) {
    return Status(StatusCode::kInvalidArgument, "point " + std::to_string(bad) + " has a non-finite coordinate");
  }
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : points_mm) centroid += p;
  centroid /= static_cast<double>(n);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : points_mm) cov += (p - centroid) * (p - centroid).transpose();
  if (cov.trace() == 0) return Status(StatusCode::kDegenerate, "3D straightness: all points coincide");
  const Eigen::Vector3d d0 = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvectors().col(2);

  internal::AxisProblem problem(points_mm, centroid, d0, internal::ChebyshevKind::kUpper);
  const double r0 = problem.Distances().maxCoeff();
  const internal::SlpResult slp =
      internal::RunSlp(problem, options.max_iterations, std::max(r0, 1e-9 * problem.Scale()));
  if (!slp.converged) return Status(StatusCode::kNotConverged, "3D straightness: " + slp.message);

  StraightnessZone3 out;
  out.n_points = n;
  out.iterations = slp.iterations;
  const Eigen::VectorXd dist = problem.Distances();
  const double radius = dist.maxCoeff();
  out.diameter_mm = 2 * radius;
  // Axial extremes and the spread check.
  const auto& q = problem.local();
  std::size_t ia = 0, ib = 0;
  for (std::size_t i = 1; i < n; ++i) {
    if (q[i].z() < q[ia].z()) ia = i;
    if (q[i].z() > q[ib].z()) ib = i;
  }
  const double s = q[ib].z() - q[ia].z();
  const double t = std::hypot(q[ib].x() - q[ia].x(), q[ib].y() - q[ia].y());
  if (!(s > out.diameter_mm)) {
    return Status(StatusCode::kDegenerate, "3D straightness: the points do not spread along a line (extent " +
                                               std::to_string(s) + " mm <= zone diameter " +
                                               std::to_string(out.diameter_mm) + " mm)");
  }
  Eigen::Vector3d dir = problem.direction();
  if (dir.dot(points_mm[n - 1] - points_mm[0]) < 0) dir = -dir;
  out.axis = Line3{problem.origin() + problem.direction().dot(centroid - problem.origin()) * problem.direction(), dir};

  ZoneCertificate& cert = out.certificate;
  cert.method = "sequential exact LP (CGAL Gmpzf) on the slanted-distance model; global lower bound";
  for (const ZoneContact& c : slp.last_lp.active) cert.contacts.push_back({c.index, ZoneSide::kUpper});
  internal::NormalizeContacts(&cert.contacts);

  // Global lower bound (see top of file).
  const internal::LinearModel model = problem.Linearize();
  const double big = 1e3 * (problem.Scale() + radius);
  internal::WorkingSet ws;
  const internal::LpResult lp =
      internal::SolveChebyshevLp(model, internal::ChebyshevKind::kUpper, internal::LpBox::Cube(4, big), &ws);
  std::ostringstream msg;
  if (!lp.ok || lp.delta.cwiseAbs().maxCoeff() > 0.5 * big) {
    msg << "global bound not available (" << (lp.ok ? "LP minimum at the box" : lp.message) << ")";
    cert.message = msg.str();
    return out;
  }
  // Rounding of the local coordinates and of the model (a few ulps of the scale).
  const double lp_star = std::max(0.0, lp.objective_lower - 32 * kStraightnessU * problem.Scale());
  const double t_up = t + 8 * kStraightnessU * problem.Scale();
  auto bound_a = [&](double th) { return 2 * lp_star * std::cos(th); };
  auto bound_b = [&](double th) { return s * std::sin(th) - t_up; };
  double lo = 0, hi = std::numbers::pi / 2;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (bound_b(mid) < bound_a(mid) ? lo : hi) = mid;
  }
  const double lower = std::max(0.0, std::min(bound_a(hi), bound_b(lo)));  // crossing in [lo, hi]
  const double reported_up = out.diameter_mm * (1 + 4 * kStraightnessU) + 16 * kStraightnessU * problem.Scale();
  cert.optimality_gap_mm = std::max(0.0, reported_up - lower);
  cert.scope = OptimalityScope::kGlobal;
  cert.verified_optimal = cert.optimality_gap_mm <= options.gap_tolerance_mm;
  msg << "proven: every line in space has a zone diameter >= " << lower << " mm (exact LP bound "
      << 2 * lp_star << " mm on the slanted model, tilt cut-off " << hi << " rad)";
  cert.message = msg.str();
  return out;
}

}  // namespace tpcal::fitting
