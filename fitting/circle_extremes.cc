// Minimum circumscribed and maximum inscribed circles (ISO 12181 MCCI, MICI): thin wrappers over
// the exact 2D geometry of minimum_zone_exact2.cc that add input checks and the certificate.
#include <algorithm>
#include <cmath>
#include <limits>

#include "fitting/minimum_zone.h"
#include "fitting/minimum_zone_exact.h"
#include "fitting/minimum_zone_lp.h"

namespace tpcal::fitting {
namespace {

double PeakToValley(std::span<const Eigen::Vector2d> pts, const Eigen::Vector2d& c) {
  double hi = 0, lo = std::numeric_limits<double>::infinity();
  for (const auto& p : pts) {
    const double r = (p - c).norm();
    hi = std::max(hi, r);
    lo = std::min(lo, r);
  }
  return hi - lo;
}

Status CheckInput(std::span<const Eigen::Vector2d> pts, std::size_t min_points, const char* what) {
  if (pts.size() < min_points) {
    return {StatusCode::kTooFewPoints, std::string(what) + " needs at least " + std::to_string(min_points) +
                                           " points, got " + std::to_string(pts.size())};
  }
  if (const long bad = internal::FirstNonFinite(pts); bad >= 0) {
    return {StatusCode::kInvalidArgument, "point " + std::to_string(bad) + " has a non-finite coordinate"};
  }
  return Status::Ok();
}

ReferenceCircle MakeResult(std::span<const Eigen::Vector2d> pts, internal::ExactCircle&& c, const char* method,
                           const char* message) {
  ReferenceCircle out;
  out.circle = Circle2{c.center_mm, c.radius_mm};
  out.peak_to_valley_mm = PeakToValley(pts, c.center_mm);
  out.n_points = pts.size();
  ZoneCertificate& cert = out.certificate;
  cert.contacts = std::move(c.contacts);
  internal::NormalizeContacts(&cert.contacts);
  cert.scope = OptimalityScope::kGlobal;
  cert.exact = true;
  cert.verified_optimal = true;
  cert.optimality_gap_mm = 0;
  cert.method = method;
  cert.message = message;
  return out;
}

}  // namespace

Result<ReferenceCircle> MinimumCircumscribedCircle(std::span<const Eigen::Vector2d> points_mm,
                                                   const ZoneOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  TPCAL_RETURN_IF_ERROR(CheckInput(points_mm, 2, "minimum circumscribed circle"));
  internal::ExactCircle c = internal::MinCircumscribedCircle2(points_mm);
  if (!c.ok) {
    const bool degenerate = c.message == "all points coincide";
    return Status(degenerate ? StatusCode::kDegenerate : StatusCode::kInternal,
                  "minimum circumscribed circle: " + c.message);
  }
  return MakeResult(points_mm, std::move(c), "CGAL Min_circle_2, exact kernel (Epeck)",
                    "exact: unique smallest enclosing circle; every point inside, contacts on it");
}

Result<ReferenceCircle> MaximumInscribedCircle(std::span<const Eigen::Vector2d> points_mm,
                                               const ZoneOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  TPCAL_RETURN_IF_ERROR(CheckInput(points_mm, 3, "maximum inscribed circle"));
  if (internal::AllCollinear2(points_mm)) {
    return Status(StatusCode::kDegenerate, "maximum inscribed circle: the points are collinear");
  }
  internal::ExactCircle c = internal::MaxInscribedCircle2(points_mm);
  if (!c.ok) return Status(StatusCode::kInternal, "maximum inscribed circle: " + c.message);
  return MakeResult(points_mm, std::move(c), "Delaunay (exact predicates), Voronoi vertices and hull crossings",
                    "exact: no point strictly inside, centre in the convex hull, largest over all "
                    "Voronoi candidates (ties decided in rationals)");
}

}  // namespace tpcal::fitting
