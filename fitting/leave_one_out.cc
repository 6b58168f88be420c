#include "fitting/leave_one_out.h"

#include <Eigen/QR>
#include <cmath>
#include <string>

namespace tpcal::fitting {

Result<LeaveOneOut> ComputeLeaveOneOut(const Eigen::MatrixXd& jacobian, std::span<const double> residuals) {
  const Eigen::Index n = jacobian.rows(), p = jacobian.cols();
  if (static_cast<std::size_t>(n) != residuals.size()) {
    return Status(StatusCode::kInvalidArgument, "ComputeLeaveOneOut: jacobian has " + std::to_string(n) +
                                                    " rows but there are " + std::to_string(residuals.size()) +
                                                    " residuals (fit with keep_jacobian and keep_residuals)");
  }
  if (n <= p) {
    return Status(StatusCode::kTooFewPoints, "ComputeLeaveOneOut needs more observations (" + std::to_string(n) +
                                                 ") than parameters (" + std::to_string(p) + ")");
  }
  const Eigen::Map<const Eigen::VectorXd> r(residuals.data(), n);
  if (!jacobian.allFinite() || !r.allFinite()) {
    return Status(StatusCode::kInvalidArgument, "ComputeLeaveOneOut: non-finite jacobian or residuals");
  }
  // J = Q R: (J^T J)^-1 j_i = R^-1 Q_i^T and h_ii = |Q_i|^2 (Q thin, n x p).
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(jacobian);
  const Eigen::MatrixXd rmat = qr.matrixQR().topRows(p).triangularView<Eigen::Upper>();
  const Eigen::VectorXd rdiag = rmat.diagonal().cwiseAbs();
  if (!(rdiag.minCoeff() > 1e-13 * rdiag.maxCoeff())) {
    return Status(StatusCode::kDegenerate, "ComputeLeaveOneOut: the jacobian is rank-deficient");
  }
  const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(n, p);
  LeaveOneOut out;
  out.leverage = q.rowwise().squaredNorm();
  out.press_residuals.resize(n);
  // delta^T (p x n) = R^-1 Q^T diag(r / (1 - h)).
  Eigen::MatrixXd scaled_qt = q.transpose();
  for (Eigen::Index i = 0; i < n; ++i) {
    const double one_minus_h = 1.0 - out.leverage[i];
    if (!(one_minus_h > 1e-12)) {
      return Status(StatusCode::kNotIdentifiable, "ComputeLeaveOneOut: observation " + std::to_string(i) +
                                                      " has leverage 1: without it the parameters are not determined");
    }
    out.press_residuals[i] = r[i] / one_minus_h;
    scaled_qt.col(i) *= out.press_residuals[i];
  }
  out.delta = rmat.triangularView<Eigen::Upper>().solve(scaled_qt).transpose();
  return out;
}

Eigen::MatrixXd JackknifeCovariance(const LeaveOneOut& loo) {
  const Eigen::Index n = loo.delta.rows();
  const Eigen::RowVectorXd mean = loo.delta.colwise().mean();
  const Eigen::MatrixXd c = loo.delta.rowwise() - mean;
  return (static_cast<double>(n - 1) / static_cast<double>(n)) * (c.transpose() * c);
}

}  // namespace tpcal::fitting
