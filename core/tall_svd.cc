#include "core/tall_svd.h"

#include <Eigen/QR>
#include <Eigen/SVD>

namespace tpcal {

TallSvdResult TallSvd(const Eigen::MatrixXd& A, bool compute_u) {
  TallSvdResult out;
  const Eigen::Index n = A.rows(), p = A.cols();
  if (n <= 2 * p) {
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, (compute_u ? Eigen::ComputeThinU : 0) | Eigen::ComputeFullV);
    out.sigma = svd.singularValues();
    out.V = svd.matrixV();
    if (compute_u) out.U = svd.matrixU();
    return out;
  }
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(A);
  const Eigen::MatrixXd R = qr.matrixQR().topRows(p).triangularView<Eigen::Upper>();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(R, (compute_u ? Eigen::ComputeFullU : 0) | Eigen::ComputeFullV);
  out.sigma = svd.singularValues();
  out.V = svd.matrixV();
  if (compute_u) {
    out.U = Eigen::MatrixXd::Zero(n, p);
    out.U.topRows(p) = svd.matrixU();
    out.U.applyOnTheLeft(qr.householderQ());
  }
  return out;
}

}  // namespace tpcal
