#include "fitting/line_fit.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "fitting/internal/accurate_sum.h"
#include "fitting/internal/lm.h"
#include "fitting/internal/orientation.h"

namespace tpcal::fitting {
namespace {

// Centroid and scatter matrix of D-dimensional points in one pass (moments about the first
// point, compensated sums). Returns false if a coordinate is not finite.
template <int D>
bool Moments(std::span<const Eigen::Matrix<double, D, 1>> p, Eigen::Matrix<double, D, 1>* centroid,
             Eigen::Matrix<double, D, D>* scatter) {
  using Vec = Eigen::Matrix<double, D, 1>;
  constexpr std::size_t kN = D + D * (D + 1) / 2;
  const Vec shift = p[0];
  const auto m = internal::BlockSums<kN>(p.size(), [&](std::size_t i) {
    const Vec d = p[i] - shift;
    std::array<double, kN> a;
    std::size_t k = 0;
    for (int r = 0; r < D; ++r) a[k++] = d[r];
    for (int r = 0; r < D; ++r) {
      for (int c = r; c < D; ++c) a[k++] = d[r] * d[c];
    }
    return a;
  });
  const double nd = static_cast<double>(p.size());
  Vec mean;
  std::size_t k = 0;
  for (int r = 0; r < D; ++r) mean[r] = m[k++] / nd;
  for (int r = 0; r < D; ++r) {
    for (int c = r; c < D; ++c, ++k) (*scatter)(r, c) = (*scatter)(c, r) = m[k];
  }
  *scatter -= nd * mean * mean.transpose();
  *centroid = shift + mean;
  return centroid->allFinite() && scatter->allFinite();
}

template <int D>
Status CheckLineInput(std::span<const Eigen::Matrix<double, D, 1>> p, const FitOptions& options, const char* what) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  if (p.size() < 2) {
    return Status(StatusCode::kTooFewPoints, std::string(what) + " needs at least 2 points, got " + std::to_string(p.size()));
  }
  return Status::Ok();
}

template <int D>
Status NonFinite(std::span<const Eigen::Matrix<double, D, 1>> p, const char* what) {
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!p[i].allFinite()) return Status(StatusCode::kInvalidArgument, std::string(what) + ": point " + std::to_string(i) + " is not finite");
  }
  return Status(StatusCode::kInvalidArgument, std::string(what) + ": moments are not finite (coordinates too large)");
}

// The major eigenvector is the direction when it is separated from the next eigenvalue:
// 1e-12 of the largest (a spread ratio of 1e-6) is the limit.
template <int D>
Status CheckDirection(const Eigen::Matrix<double, D, 1>& lambda, const char* what) {
  if (!(lambda[D - 1] > 0.0)) return Status(StatusCode::kDegenerate, std::string(what) + ": all points coincide");
  if (lambda[D - 1] - lambda[D - 2] <= 1e-12 * lambda[D - 1]) {
    std::ostringstream os;
    os << what << ": the points have no dominant direction (scatter eigenvalues " << lambda.transpose()
       << " mm^2): not a line";
    return Status(StatusCode::kDegenerate, os.str());
  }
  return Status::Ok();
}

}  // namespace

Result<FitResult<Line2>> FitLine2(std::span<const Eigen::Vector2d> points_mm, const FitOptions& options) {
  TPCAL_RETURN_IF_ERROR(CheckLineInput<2>(points_mm, options, "FitLine2"));
  const std::size_t n = points_mm.size();
  Eigen::Vector2d centroid;
  Eigen::Matrix2d scatter;
  if (!Moments<2>(points_mm, &centroid, &scatter)) return NonFinite<2>(points_mm, "FitLine2");
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(scatter);
  const Eigen::Vector2d lambda = es.eigenvalues().cwiseMax(0.0);
  TPCAL_RETURN_IF_ERROR(CheckDirection<2>(lambda, "FitLine2"));
  Eigen::Vector2d dir = es.eigenvectors().col(1);
  const double along = dir.dot(points_mm[n - 1] - points_mm[0]);
  if (along < 0.0 || (along == 0.0 && (dir.x() < 0.0 || (dir.x() == 0.0 && dir.y() < 0.0)))) dir = -dir;
  const Line2 line{centroid, dir};
  FitResult<Line2> r;
  r.feature = line;
  r.n_points = n;
  r.parameter_names = {"offset_mm", "angle_rad"};
  r.local_axes.col(0) << -dir.y(), dir.x(), 0.0;  // offset direction (left normal)
  r.local_axes.col(1) << dir.x(), dir.y(), 0.0;   // the line direction
  r.local_axes.col(2) = Eigen::Vector3d::UnitZ();
  if (options.keep_residuals) r.residuals_mm.resize(n);
  if (options.keep_jacobian) r.jacobian.resize(static_cast<Eigen::Index>(n), 2);
  const internal::ValueSums ss = internal::SumValues(
      n, [&](std::size_t i) { return SignedDistance(line, points_mm[i]); },
      options.keep_residuals ? r.residuals_mm.data() : nullptr);
  if (options.keep_jacobian) {
    // Offset along the left normal lowers r by 1; turning the line by +angle lowers r by
    // the along-line coordinate s.
    for (std::size_t i = 0; i < n; ++i) {
      r.jacobian.row(static_cast<Eigen::Index>(i)) << -1.0, -dir.dot(points_mm[i] - centroid);
    }
  }
  r.stats = internal::MakeStats(ss.sum_sq, ss.min, ss.max, n, 2);
  if (options.compute_covariance && n > 2) {
    const double sigma2 = ss.sum_sq / static_cast<double>(n - 2);
    r.covariance = Eigen::Vector2d(sigma2 / static_cast<double>(n), sigma2 / lambda[1]).asDiagonal();
  }
  r.termination = Termination::kClosedForm;
  r.message = "closed form (centroid and scatter eigenvector), " + std::to_string(n) + " points";
  return r;
}

Result<FitResult<Line3>> FitLine3(std::span<const Eigen::Vector3d> points_mm, const FitOptions& options) {
  TPCAL_RETURN_IF_ERROR(CheckLineInput<3>(points_mm, options, "FitLine3"));
  const std::size_t n = points_mm.size();
  Eigen::Vector3d centroid;
  Eigen::Matrix3d scatter;
  if (!Moments<3>(points_mm, &centroid, &scatter)) return NonFinite<3>(points_mm, "FitLine3");
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(scatter);
  const Eigen::Vector3d lambda = es.eigenvalues().cwiseMax(0.0);
  TPCAL_RETURN_IF_ERROR(CheckDirection<3>(lambda, "FitLine3"));
  Eigen::Vector3d dir = es.eigenvectors().col(2);
  const double along = dir.dot(points_mm[n - 1] - points_mm[0]);
  dir = along > 0.0 ? dir : (along < 0.0 ? Eigen::Vector3d(-dir) : internal::OrientByAxesRule(dir));
  const Eigen::Vector3d u = es.eigenvectors().col(1);
  const Eigen::Vector3d v = dir.cross(u);
  FitResult<Line3> r;
  r.feature = Line3{centroid, dir};
  r.n_points = n;
  r.parameter_names = {"offset_u_mm", "offset_v_mm", "tilt_u_rad", "tilt_v_rad"};
  r.local_axes.col(0) = u;
  r.local_axes.col(1) = v;
  r.local_axes.col(2) = dir;
  if (options.keep_residuals) r.residuals_mm.resize(n);
  const internal::ValueSums ss = internal::SumValues(
      n, [&](std::size_t i) { return dir.cross(points_mm[i] - centroid).norm(); },
      options.keep_residuals ? r.residuals_mm.data() : nullptr);
  // Two residual components per point, four parameters: sigma per component.
  r.stats = internal::MakeStats(ss.sum_sq, ss.min, ss.max, n, 2);
  r.stats.sigma_mm = n > 2 ? std::sqrt(ss.sum_sq / static_cast<double>(2 * n - 4)) : 0.0;
  if (options.compute_covariance && n > 2) {
    // J^T J = diag(n, n, sum s^2, sum s^2) about the centroid, sum s^2 = largest eigenvalue.
    const double sigma2 = ss.sum_sq / static_cast<double>(2 * n - 4);
    const double nd = static_cast<double>(n);
    r.covariance = Eigen::Vector4d(sigma2 / nd, sigma2 / nd, sigma2 / lambda[2], sigma2 / lambda[2]).asDiagonal();
  }
  r.termination = Termination::kClosedForm;
  r.message = "closed form (centroid and scatter eigenvector), " + std::to_string(n) + " points";
  return r;
}

}  // namespace tpcal::fitting
