#include "kinematics/internal/scaled_solve.h"

#include <Eigen/SVD>
#include <cmath>

namespace tpcal::kinematics::internal {

bool ScaledSolve::Determined(int column) const {
  return scale(column) > 0.0 && std::abs(v.row(column).squaredNorm() - 1.0) < 1e-6;
}

ScaledSolve SolveScaled(const Eigen::MatrixXd& a, double rank_tolerance, double min_norm) {
  ScaledSolve out;
  out.scale.resize(a.cols());
  for (Eigen::Index c = 0; c < a.cols(); ++c) {
    const double n = a.col(c).norm();
    out.scale(c) = n > min_norm ? 1.0 / n : 0.0;
  }
  Eigen::BDCSVD<Eigen::MatrixXd> svd(a * out.scale.asDiagonal(), Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& sv = svd.singularValues();
  while (out.rank < sv.size() && sv(out.rank) > rank_tolerance * sv(0)) ++out.rank;
  out.v = svd.matrixV().leftCols(out.rank);
  out.m = out.scale.asDiagonal() * out.v * sv.head(out.rank).cwiseInverse().asDiagonal() *
          svd.matrixU().leftCols(out.rank).transpose();
  return out;
}

}  // namespace tpcal::kinematics::internal
