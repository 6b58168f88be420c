#include "core/tall_qr.h"

#include <algorithm>

namespace tpcal {

TallQr::TallQr(Eigen::MatrixXd* A) : n_(A->rows()), p_(A->cols()) {
  // Blocks of kTallQrBlockRows rows (at least 2p, so each R has p rows); the remainder joins the
  // last block.
  const Eigen::Index rows = std::max(kTallQrBlockRows, 2 * p_);
  const Eigen::Index nb = std::max<Eigen::Index>(1, n_ / rows);
  for (Eigen::Index b = 0; b < nb; ++b) begin_.push_back(b * rows);
  begin_.push_back(n_);
  blocks_.reserve(static_cast<std::size_t>(nb));
  for (Eigen::Index b = 0; b < nb; ++b) {
    Eigen::Ref<Eigen::MatrixXd> block = A->middleRows(begin_[b], begin_[b + 1] - begin_[b]);
    blocks_.emplace_back(block);
  }
  if (nb == 1) return;
  // Every block has >= 2p rows, so its R is p x p.
  stacked_.setZero(nb * p_, p_);
  for (Eigen::Index b = 0; b < nb; ++b) {
    stacked_.middleRows(b * p_, p_) = blocks_[static_cast<std::size_t>(b)].matrixQR().topRows(p_).triangularView<Eigen::Upper>();
  }
  Eigen::Ref<Eigen::MatrixXd> s = stacked_;
  top_ = std::make_unique<BlockQr>(s);
}

Eigen::MatrixXd TallQr::R() const {
  const Eigen::Index m = std::min(n_, p_);
  const auto& f = top_ ? top_->matrixQR() : blocks_.front().matrixQR();
  return f.topRows(m).triangularView<Eigen::Upper>();
}

namespace {

// dst = Q dst for the Householder factorisation `qr`, by the compact WY form (I - V T V^T): two
// matrix products instead of one memory pass per reflector (Eigen applies reflectors one by one
// below 48 of them).
template <typename Qr, typename Dst>
void ApplyBlockQ(const Qr& qr, Dst& dst) {
  const Eigen::Index k = qr.hCoeffs().size();
  if (k == 0) return;
  Eigen::internal::apply_block_householder_on_the_left(dst, qr.matrixQR().leftCols(k), qr.hCoeffs(), /*forward=*/true);
}

}  // namespace

Eigen::MatrixXd TallQr::ApplyQ(const Eigen::MatrixXd& S) const {
  const Eigen::Index m = std::min(n_, p_), k = S.cols();
  Eigen::MatrixXd out(n_, k);  // every block writes all its rows
  if (!top_) {
    out.setZero();
    out.topRows(m) = S.topRows(m);
    ApplyBlockQ(blocks_.front(), out);
    return out;
  }
  Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(stacked_.rows(), k);
  Y.topRows(m) = S.topRows(m);
  ApplyBlockQ(*top_, Y);
  for (std::size_t b = 0; b < blocks_.size(); ++b) {
    const Eigen::Index r0 = begin_[b], nr = begin_[b + 1] - begin_[b];
    auto ob = out.middleRows(r0, nr);
    ob.setZero();
    ob.topRows(p_) = Y.middleRows(static_cast<Eigen::Index>(b) * p_, p_);  // block b's R rows
    ApplyBlockQ(blocks_[b], ob);
  }
  return out;
}

}  // namespace tpcal
