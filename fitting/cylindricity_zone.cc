// Minimum-zone cylindricity (ISO 12180 MZCY): minimise R - r of two coaxial cylinders over the axis.
//
// Sequential exact LP/QP (minimum_zone_lp.h) from the least-squares cylinder, in the axis
// parametrisation of minimum_zone_axis.h (displacements A, B of the axis at the two ends of the
// data, in mm). Local certificate: for ||(A, B)||_inf <= t,
//   zone(A, B) >= L(A, B) - Q(t),  Q(t) = t^2 / (r_min - sqrt2 t) + 4 t^2 (r_max + sqrt2 t) / H^2,
// where L is the piecewise-linear LP model: the first term bounds the inner distances from above
// (|w| <= u.w + |w_perp|^2 / (2 u.w)), the second the tilt (true distance >= cos(theta) x slanted
// distance, 1 - cos(theta) <= tan^2(theta) / 2, tan(theta) <= 2 sqrt2 t / H). Exact LPs on small
// boxes then prove that no cylinder within the certified radius has a narrower zone than
// width - gap. The problem is not convex: a global guarantee is not claimed.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "fitting/cylinder_fit.h"
#include "fitting/minimum_zone.h"
#include "fitting/minimum_zone_axis.h"
#include "fitting/minimum_zone_exact.h"
#include "fitting/minimum_zone_lp.h"

namespace tpcal::fitting {

Result<CylindricityZone> MinimumZoneCylindricity(std::span<const Eigen::Vector3d> points_mm, const ZoneOptions& options,
                                                 std::optional<Cylinder> start) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  const std::size_t n = points_mm.size();
  if (n < 6) {
    return Status(StatusCode::kTooFewPoints, "minimum-zone cylindricity needs at least 6 points, got " + std::to_string(n));
  }
  if (const long bad = internal::FirstNonFinite(points_mm); bad >= 0) {
    return Status(StatusCode::kInvalidArgument, "point " + std::to_string(bad) + " has a non-finite coordinate");
  }
  if (!start) {
    FitOptions fo;
    fo.compute_covariance = false;
    fo.keep_residuals = false;
    const auto ls = FitCylinder(points_mm, fo);
    if (!ls.ok()) return ls.status().WithContext("minimum-zone cylindricity: least-squares start");
    start = ls->feature;
  }
  if (!start->axis.allFinite() || start->axis.norm() == 0 || !start->point_mm.allFinite()) {
    return Status(StatusCode::kInvalidArgument, "minimum-zone cylindricity: invalid start axis");
  }

  internal::AxisProblem problem(points_mm, start->point_mm, start->axis, internal::ChebyshevKind::kZone);
  if (!(problem.z_hi() > problem.z_lo())) {
    return Status(StatusCode::kDegenerate, "minimum-zone cylindricity: the points have no extent along the axis");
  }
  const Eigen::VectorXd d0 = problem.Distances();
  if (!(d0.minCoeff() > 0)) {
    return Status(StatusCode::kDegenerate, "minimum-zone cylindricity: a point lies on the start axis");
  }
  const double step0 = std::max(0.05 * d0.mean(), 1e-9 * problem.Scale());
  const internal::SlpResult slp = internal::RunSlp(problem, options.max_iterations, step0);
  if (!slp.converged) return Status(StatusCode::kNotConverged, "minimum-zone cylindricity: " + slp.message);

  CylindricityZone out;
  out.n_points = n;
  out.iterations = slp.iterations;
  const Eigen::VectorXd d = problem.Distances();
  out.r_inner_mm = d.minCoeff();
  out.r_outer_mm = d.maxCoeff();
  out.width_mm = out.r_outer_mm - out.r_inner_mm;
  if (!(out.r_inner_mm > 0)) {
    return Status(StatusCode::kDegenerate, "minimum-zone cylindricity: the zone reaches the axis (not a cylinder)");
  }
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : points_mm) centroid += p;
  centroid /= static_cast<double>(n);
  Eigen::Vector3d axis = problem.direction();
  if (axis.dot(start->axis) < 0) axis = -axis;
  out.axis = Line3{problem.origin() + axis.dot(centroid - problem.origin()) * axis, axis};

  ZoneCertificate& cert = out.certificate;
  cert.method = "sequential exact LP/QP (CGAL Gmpzf) from the least-squares cylinder; local certificate";
  cert.contacts = slp.last_lp.active;
  internal::NormalizeContacts(&cert.contacts);

  const double r_min = out.r_inner_mm, r_max = out.r_outer_mm, h = problem.z_hi() - problem.z_lo();
  const double sqrt2 = std::sqrt(2.0);
  const auto q = [=](double t) {
    if (!(sqrt2 * t < 0.5 * r_min)) return std::numeric_limits<double>::infinity();
    return t * t / (r_min - sqrt2 * t) + 4 * t * t * (r_max + sqrt2 * t) / (h * h);
  };
  const internal::LocalCertificate local = internal::CertifyLocal(problem, out.width_mm, q, 0.25 * r_min);
  std::ostringstream msg;
  if (local.ok) {
    cert.scope = OptimalityScope::kLocal;
    cert.optimality_gap_mm = local.gap_mm;
    cert.certified_radius_mm = local.radius_mm;
    cert.verified_optimal = local.gap_mm <= options.gap_tolerance_mm && local.radius_mm > 0;
    msg << "local: no cylinder whose axis ends move by <= " << local.radius_mm << " mm has a zone narrower than "
        << out.width_mm - local.gap_mm << " mm (" << local.message << "); not a global guarantee";
  } else {
    msg << "local certificate failed: " << local.message;
  }
  cert.message = msg.str();
  return out;
}

}  // namespace tpcal::fitting
