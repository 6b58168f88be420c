// The minimum-norm least-squares solve both linear steps of a map instrument use: columns scaled
// to unit norm, thin SVD, singular values at most `rank_tolerance` of the largest dropped.
#pragma once

#include <Eigen/Core>

namespace tpcal::kinematics::internal {

struct ScaledSolve {
  Eigen::MatrixXd m;      // x = m * y (unscaled columns)
  Eigen::MatrixXd v;      // the kept right singular vectors, one row per column
  Eigen::VectorXd scale;  // 1 / column norm; 0 for a column of norm at most min_norm
  int rank = 0;
  // The column's unit vector lies in the row space (|V_r^T e_c| = 1): its unknown is determined.
  bool Determined(int column) const;
};

ScaledSolve SolveScaled(const Eigen::MatrixXd& a, double rank_tolerance = 1e-9, double min_norm = 0.0);

}  // namespace tpcal::kinematics::internal
