// Axis parametrisation for the 3D straightness and cylindricity refinements (minimum_zone_axis.h).
#include "fitting/minimum_zone_axis.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace tpcal::fitting::internal {

AxisProblem::AxisProblem(std::span<const Eigen::Vector3d> pts, const Eigen::Vector3d& point_mm,
                         const Eigen::Vector3d& direction, ChebyshevKind kind)
    : pts_(pts), kind_(kind), rotation_(Eigen::Matrix3d::Identity()) {
  Reframe(point_mm, direction.normalized());
}

void AxisProblem::Reframe(const Eigen::Vector3d& origin, const Eigen::Vector3d& u) {
  // Keep e1 close to the previous one so that the parameters stay continuous.
  Eigen::Vector3d e1 = rotation_.col(0) - rotation_.col(0).dot(u) * u;
  if (e1.norm() < 0.5) {
    e1 = std::abs(u.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    e1 -= e1.dot(u) * u;
  }
  e1.normalize();
  const Eigen::Vector3d e2 = u.cross(e1);
  rotation_.col(0) = e1;
  rotation_.col(1) = e2;
  rotation_.col(2) = u;
  origin_ = origin;
  local_.resize(pts_.size());
  z_lo_ = std::numeric_limits<double>::infinity();
  z_hi_ = -z_lo_;
  scale_ = 0;
  for (std::size_t i = 0; i < pts_.size(); ++i) {
    local_[i] = rotation_.transpose() * (pts_[i] - origin_);
    z_lo_ = std::min(z_lo_, local_[i].z());
    z_hi_ = std::max(z_hi_, local_[i].z());
    scale_ = std::max(scale_, local_[i].norm());
  }
  // Re-centre the origin along the axis (keeps the local numbers small and symmetric).
  const double mid = 0.5 * (z_lo_ + z_hi_);
  if (mid != 0) {
    origin_ += mid * u;
    for (auto& q : local_) q.z() -= mid;
    z_lo_ -= mid;
    z_hi_ -= mid;
  }
}

LinearModel AxisProblem::Linearize() const {
  const int n = static_cast<int>(local_.size());
  LinearModel m;
  m.value.resize(n);
  m.jacobian.resize(n, 4);
  const double h = z_hi_ - z_lo_;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d& q = local_[i];
    const double r = std::hypot(q.x(), q.y());
    m.value[i] = r;
    const double tau = h > 0 ? (q.z() - z_lo_) / h : 0.5;
    if (r > 0) {
      const double ux = q.x() / r, uy = q.y() / r;
      m.jacobian.row(i) << -(1 - tau) * ux, -(1 - tau) * uy, -tau * ux, -tau * uy;
    } else {
      m.jacobian.row(i).setZero();
    }
  }
  return m;
}

double AxisProblem::Objective(const Eigen::VectorXd& delta) const {
  const Eigen::Vector3d a(delta[0], delta[1], z_lo_), b(delta[2], delta[3], z_hi_);
  const Eigen::Vector3d v = (b - a).normalized();
  double hi = 0, lo = std::numeric_limits<double>::infinity();
  for (const auto& q : local_) {
    const double d = (q - a).cross(v).norm();
    hi = std::max(hi, d);
    lo = std::min(lo, d);
  }
  return kind_ == ChebyshevKind::kZone ? hi - lo : hi;
}

void AxisProblem::Apply(const Eigen::VectorXd& delta) {
  const Eigen::Vector3d a(delta[0], delta[1], z_lo_), b(delta[2], delta[3], z_hi_);
  const Eigen::Vector3d origin = origin_ + rotation_ * (0.5 * (a + b));
  const Eigen::Vector3d u = (rotation_ * (b - a)).normalized();
  Reframe(origin, u);
}

Eigen::MatrixXd AxisProblem::Curvature(const std::vector<ZoneContact>& active,
                                       const std::vector<double>& multipliers) const {
  // Hessian of the slanted distance |w_i - E_i delta|: E_i^T (I - u u^T) E_i / r_i, E_i = [(1-tau) I, tau I].
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(4, 4);
  const double h = z_hi_ - z_lo_;
  for (std::size_t a = 0; a < active.size(); ++a) {
    if (active[a].side != ZoneSide::kUpper) continue;  // inner rows are concave: left out
    const Eigen::Vector3d& q = local_[active[a].index];
    const double r = std::hypot(q.x(), q.y());
    if (r <= 0) continue;
    const Eigen::Vector2d u(q.x() / r, q.y() / r);
    const Eigen::Matrix2d p = (Eigen::Matrix2d::Identity() - u * u.transpose()) / r;
    const double tau = h > 0 ? (q.z() - z_lo_) / h : 0.5;
    Eigen::Matrix<double, 2, 4> e;
    e << (1 - tau) * Eigen::Matrix2d::Identity(), tau * Eigen::Matrix2d::Identity();
    w += multipliers[a] * e.transpose() * p * e;
  }
  return 0.5 * (w + w.transpose());
}

Eigen::VectorXd AxisProblem::Distances() const {
  Eigen::VectorXd d(local_.size());
  for (std::size_t i = 0; i < local_.size(); ++i) d[i] = std::hypot(local_[i].x(), local_[i].y());
  return d;
}

}  // namespace tpcal::fitting::internal
