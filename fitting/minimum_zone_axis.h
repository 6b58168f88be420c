// Internal to fitting/: an axis (line in space) parametrised for the sequential-LP refinements of
// 3D straightness and cylindricity. Not a public API.
//
// Local frame: origin o on the axis, orthonormal (e1, e2, u) with u the axis direction; point i
// has local coordinates q_i = R^T (p_i - o). A displaced axis is given by delta = (A, B) in mm: it
// passes through (A_x, A_y, z_lo) and (B_x, B_y, z_hi) in the local frame, z_lo / z_hi being the
// lowest / highest local z of the data. Residual r_i = distance of p_i to the axis.
// Linearisation at delta = 0 ("slanted" distances measured in the planes z = const, which are
// convex in delta): r_i(delta) ~ r_i - u_i . ((1 - tau_i) A + tau_i B), tau_i = (z_i - z_lo) / H.
#pragma once

#include <Eigen/Core>
#include <span>

#include "fitting/features.h"
#include "fitting/minimum_zone_lp.h"

namespace tpcal::fitting::internal {

class AxisProblem final : public ChebyshevProblem {
 public:
  AxisProblem(std::span<const Eigen::Vector3d> pts, const Eigen::Vector3d& point_mm,
              const Eigen::Vector3d& direction, ChebyshevKind kind);

  int num_params() const override { return 4; }
  ChebyshevKind kind() const override { return kind_; }
  LinearModel Linearize() const override;
  double Objective(const Eigen::VectorXd& delta) const override;
  void Apply(const Eigen::VectorXd& delta) override;
  Eigen::MatrixXd Curvature(const std::vector<ZoneContact>& active,
                            const std::vector<double>& multipliers) const override;
  double Scale() const override { return scale_; }

  const Eigen::Vector3d& origin() const { return origin_; }
  Eigen::Vector3d direction() const { return rotation_.col(2); }
  const Eigen::Matrix3d& rotation() const { return rotation_; }
  double z_lo() const { return z_lo_; }
  double z_hi() const { return z_hi_; }
  const std::vector<Eigen::Vector3d>& local() const { return local_; }
  // Distances of the points to the current axis (mm).
  Eigen::VectorXd Distances() const;

 private:
  void Reframe(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction);

  std::span<const Eigen::Vector3d> pts_;
  ChebyshevKind kind_;
  Eigen::Vector3d origin_;
  Eigen::Matrix3d rotation_;
  std::vector<Eigen::Vector3d> local_;
  double z_lo_ = 0, z_hi_ = 0, scale_ = 1;
};

}  // namespace tpcal::fitting::internal
