// Householder QR of a tall matrix by row blocks (TSQR): each block of about kTallQrBlockRows rows
// is factored while it sits in cache, then the stacked R factors of the blocks once more. For an
// n x p matrix with p below Eigen's blocking size (48) the plain factorisation makes p passes
// over the whole matrix (memory-bound at millions of rows); this makes p passes over each block
// in cache. R equals the plain factor up to the signs of its rows; backward stable like it.
// The factorisation works in place on the caller's matrix (which it then holds the reflectors of).
#pragma once

#include <Eigen/Core>
#include <Eigen/QR>
#include <memory>
#include <vector>

namespace tpcal {

inline constexpr Eigen::Index kTallQrBlockRows = 4096;

class TallQr {
 public:
  // Factors *A (n x p, any shape) in place; *A must outlive this object and stay untouched.
  explicit TallQr(Eigen::MatrixXd* A);

  Eigen::Index rows() const { return n_; }
  Eigen::Index cols() const { return p_; }
  // The min(n, p) x p upper-triangular factor.
  Eigen::MatrixXd R() const;
  // Q [S; 0] for S with min(n, p) rows: n x S.cols() (orthonormal columns when S has them).
  Eigen::MatrixXd ApplyQ(const Eigen::MatrixXd& S) const;

 private:
  using BlockQr = Eigen::HouseholderQR<Eigen::Ref<Eigen::MatrixXd>>;
  Eigen::Index n_ = 0, p_ = 0;
  std::vector<Eigen::Index> begin_;          // first row of each block (blocks_.size() + 1 entries)
  std::vector<BlockQr> blocks_;              // in place on the rows of *A
  Eigen::MatrixXd stacked_;                  // block b's R factor in rows b p ... (factored in place)
  std::unique_ptr<BlockQr> top_;             // QR of stacked_ (absent for a single block)
};

}  // namespace tpcal
