#include "fitting/plane_fit.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <sstream>
#include <string>

#include "fitting/internal/accurate_sum.h"
#include "fitting/internal/lm.h"
#include "fitting/internal/orientation.h"

namespace tpcal::fitting {
namespace {

// Index of the first non-finite point, for the error message.
std::size_t FirstNonFinite(std::span<const Eigen::Vector3d> p) {
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!p[i].allFinite()) return i;
  }
  return p.size();
}

}  // namespace

Result<FitResult<Plane>> FitPlane(std::span<const Eigen::Vector3d> points_mm, const FitOptions& options,
                                  std::optional<Eigen::Vector3d> normal_hint) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  const std::size_t n = points_mm.size();
  if (n < 3) {
    return Status(StatusCode::kTooFewPoints, "FitPlane needs at least 3 points, got " + std::to_string(n));
  }
  // One pass: first and second moments about the first point (a point inside the data, so
  // no cancellation against a far origin), accumulated with BlockSums.
  const Eigen::Vector3d shift = points_mm[0];
  const auto m = internal::BlockSums<9>(n, [&](std::size_t i) {
    const Eigen::Vector3d d = points_mm[i] - shift;
    return std::array<double, 9>{d.x(),         d.y(),         d.z(),         d.x() * d.x(), d.x() * d.y(),
                                 d.x() * d.z(), d.y() * d.y(), d.y() * d.z(), d.z() * d.z()};
  });
  const double nd = static_cast<double>(n);
  const Eigen::Vector3d mean_d(m[0] / nd, m[1] / nd, m[2] / nd);
  if (!mean_d.allFinite()) {
    return Status(StatusCode::kInvalidArgument,
                  "FitPlane: point " + std::to_string(FirstNonFinite(points_mm)) + " is not finite");
  }
  Eigen::Matrix3d scatter;
  scatter << m[3], m[4], m[5], m[4], m[6], m[7], m[5], m[7], m[8];
  scatter -= nd * mean_d * mean_d.transpose();
  const Eigen::Vector3d centroid = shift + mean_d;

  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(scatter);  // ascending eigenvalues
  const Eigen::Vector3d lambda = es.eigenvalues().cwiseMax(0.0);
  // The normal is defined when the two smallest eigenvalues are separated; 1e-12 of the
  // largest is an in-plane width below 1e-6 of the length (collinear within rounding).
  if (!(lambda[2] > 0.0)) return Status(StatusCode::kDegenerate, "FitPlane: all points coincide");
  if (lambda[1] - lambda[0] <= 1e-12 * lambda[2]) {
    std::ostringstream os;
    os << "FitPlane: points are collinear (or isotropic): scatter eigenvalues " << lambda.transpose()
       << " mm^2 do not single out a normal";
    return Status(StatusCode::kDegenerate, os.str());
  }
  const Eigen::Vector3d normal = internal::OrientAlong(es.eigenvectors().col(0), normal_hint);
  const Eigen::Vector3d u = es.eigenvectors().col(2);  // major in-plane direction
  const Eigen::Vector3d v = normal.cross(u);           // (u, v, normal) right-handed

  FitResult<Plane> r;
  r.feature = Plane{centroid, normal};
  r.n_points = n;
  r.local_axes.col(0) = u;
  r.local_axes.col(1) = v;
  r.local_axes.col(2) = normal;
  r.parameter_names = {"offset_mm", "tilt_u_rad", "tilt_v_rad"};
  if (options.keep_residuals) r.residuals_mm.resize(n);
  if (options.keep_jacobian) r.jacobian.resize(static_cast<Eigen::Index>(n), 3);
  // Second pass: residuals n . (p - c) (and, if asked, the Jacobian rows: moving the plane
  // by +offset along the normal lowers every residual by 1; tilting the normal toward u by
  // t raises r by t * u.(p - c)).
  const internal::ValueSums ss = internal::SumValues(
      n, [&](std::size_t i) { return normal.dot(points_mm[i] - centroid); },
      options.keep_residuals ? r.residuals_mm.data() : nullptr);
  if (options.keep_jacobian) {
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d d = points_mm[i] - centroid;
      r.jacobian.row(static_cast<Eigen::Index>(i)) << -1.0, u.dot(d), v.dot(d);
    }
  }
  r.stats = internal::MakeStats(ss.sum_sq, ss.min, ss.max, n, 3);
  if (options.compute_covariance && n > 3) {
    // J^T J = diag(n, lambda_u, lambda_v): the centroid and the principal axes decouple it.
    const double sigma2 = ss.sum_sq / (nd - 3.0);
    r.covariance = Eigen::Vector3d(sigma2 / nd, sigma2 / lambda[2], sigma2 / lambda[1]).asDiagonal();
  }
  r.termination = Termination::kClosedForm;
  std::ostringstream os;
  os << "closed form (centroid and scatter eigenvector), " << n << " points";
  r.message = os.str();
  return r;
}

}  // namespace tpcal::fitting
