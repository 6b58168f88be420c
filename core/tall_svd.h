// Thin SVD of a tall matrix through its R factor: A (n x p) = Q R (Householder by row blocks,
// core/tall_qr.h, O(n p^2), no pivoting: backward stable, the singular values of R are those of A) and the two-sided Jacobi
// SVD of the p x p factor R = U_R diag(sigma) V^T; then U = Q [U_R; 0]. Several times faster than
// a Jacobi SVD of A itself, whose column-pivoting QR preconditioner is not blocked.
#pragma once

#include <Eigen/Core>

namespace tpcal {

struct TallSvdResult {
  Eigen::MatrixXd U;      // n x min(n, p) (empty unless asked for)
  Eigen::VectorXd sigma;  // min(n, p), decreasing
  Eigen::MatrixXd V;      // p x p
};

// Thin SVD of A (any shape; the QR step only when n > 2p). `compute_u`: also U.
TallSvdResult TallSvd(const Eigen::MatrixXd& A, bool compute_u);

}  // namespace tpcal
