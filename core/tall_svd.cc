#include "core/tall_svd.h"

#include "core/tall_qr.h"

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
  Eigen::MatrixXd W = A;
  const TallQr qr(&W);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(qr.R(), (compute_u ? Eigen::ComputeFullU : 0) | Eigen::ComputeFullV);
  out.sigma = svd.singularValues();
  out.V = svd.matrixV();
  if (compute_u) out.U = qr.ApplyQ(svd.matrixU());
  return out;
}

}  // namespace tpcal
