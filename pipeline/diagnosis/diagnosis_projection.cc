#include "pipeline/diagnosis/diagnosis_projection.h"

#include <Eigen/SVD>
#include <cmath>

#include "core/tall_qr.h"
#include "pipeline/diagnosis/diagnosis_least_squares.h"

namespace tpcal::pipeline::diagnosis_internal {

Columns ColumnsOf(const CandidateColumns& c) {
  Columns out;
  for (Eigen::Index j = 0; j < c.cols(); ++j) out.push_back(c.col(j));
  return out;
}
Eigen::VectorXd ColumnNorms(const Columns& C) {
  Eigen::VectorXd n(static_cast<Eigen::Index>(C.size()));
  for (std::size_t j = 0; j < C.size(); ++j) n(static_cast<Eigen::Index>(j)) = C[j].norm();
  return ZeroRoundingColumns(std::move(n));
}

Projected ProjectCandidate(const Columns& C, const Eigen::MatrixXd& Q, double tol) {
  Projected out;
  const Eigen::Index n = Q.rows(), p = static_cast<Eigen::Index>(C.size());
  out.identifiable.assign(static_cast<std::size_t>(p), false);
  out.U.resize(n, 0);
  out.B.resize(p, 0);
  if (p == 0) return out;
  const Eigen::VectorXd norms = ColumnNorms(C);
  // One n x p buffer and one QR, by row blocks and in place (core/tall_qr.h): at 2e6 points the
  // first-touch page faults of copies and the passes of a second n x p QR cost more than the rest.
  // With C_s = C diag(1/norms) (unit-norm columns), X = Q^T C_s and (I - Q Q^T) C_s = Q_2 R_2:
  // C_s = Q X + Q_2 R_2 with Q^T Q_2 = 0, so the small [X; R_2] has the Gram matrix of C_s, hence
  // its singular values and right vectors (no QR of C_s itself).
  Eigen::MatrixXd W(n, p);
  for (Eigen::Index j = 0; j < p; ++j)
    if (norms(j) > 0)
      W.col(j) = C[static_cast<std::size_t>(j)] / norms(j);
    else
      W.col(j).setZero();
  Eigen::MatrixXd X(Q.cols(), p);
  if (Q.cols() > 0) {
    X.noalias() = Q.transpose() * W;
    W.noalias() -= Q * X;
  }
  const TallQr qr2(&W);
  const Eigen::MatrixXd R2 = qr2.R();
  // 1. span(C): singular values S_c and right vectors V_c of C_s.
  Eigen::VectorXd sc;
  Eigen::MatrixXd Vc;
  {
    Eigen::MatrixXd S(X.rows() + R2.rows(), p);
    S << X, R2;
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(S, Eigen::ComputeFullV);
    sc = svd.singularValues();
    Vc = svd.matrixV();
  }
  int rc = 0;
  for (Eigen::Index k = 0; k < sc.size(); ++k)
    if (sc(k) > 1e-10 * sc(0) && sc(k) > 0) ++rc;
  if (rc == 0) return out;
  // 2. The orthonormal basis U_c = C_s V_c S_c^-1 of span(C) seen through the complement of
  // span(Q): P = (I - Q Q^T) U_c = Q_2 M with M = R_2 V_c S_c^-1 (m x rc). The SVD of M is that
  // of P; its singular values are the sines of the principal angles between span(C) and span(Q).
  Eigen::MatrixXd Vcr = Vc.leftCols(rc);
  for (int j = 0; j < rc; ++j) Vcr.col(j) /= sc(j);
  const Eigen::MatrixXd M = R2 * Vcr;
  Eigen::JacobiSVD<Eigen::MatrixXd> msvd(M, Eigen::ComputeThinU | Eigen::ComputeFullV);
  const Eigen::VectorXd& s = msvd.singularValues();
  out.max_sine = s.size() > 0 ? s(0) : 0.0;
  out.rms_sine = s.size() > 0 ? std::sqrt(s.squaredNorm() / static_cast<double>(rc)) : 0.0;
  int k = 0;
  while (k < s.size() && s(k) > tol) ++k;
  out.rank = k;
  if (k == 0) return out;
  out.U = qr2.ApplyQ(msvd.matrixU().leftCols(k));
  // x_scaled = V_c S_c^-1 (V_p S_p^-1) z; x = x_scaled / norms.
  Eigen::MatrixXd Vp = msvd.matrixV().leftCols(k);
  for (int j = 0; j < k; ++j) Vp.col(j) /= s(j);
  out.B = Vcr * Vp;
  for (Eigen::Index j = 0; j < p; ++j) out.B.row(j) /= (norms(j) > 0 ? norms(j) : 1.0);
  // Identifiable coefficients: e_j in the row space of the determined functionals F = V_p^T S_c V_c^T.
  const Eigen::MatrixXd Ft = Vc.leftCols(rc) * sc.head(rc).asDiagonal() * msvd.matrixV().leftCols(k);
  Eigen::JacobiSVD<Eigen::MatrixXd> fsvd(Ft, Eigen::ComputeThinU);
  int fr = 0;
  for (Eigen::Index j = 0; j < fsvd.singularValues().size(); ++j)
    if (fsvd.singularValues()(j) > 1e-9 * fsvd.singularValues()(0)) ++fr;
  const Eigen::MatrixXd Qf = fsvd.matrixU().leftCols(fr);
  for (Eigen::Index j = 0; j < p; ++j) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(p);
    e(j) = 1.0;
    out.identifiable[static_cast<std::size_t>(j)] = norms(j) > 0 && (e - Qf * (Qf.transpose() * e)).norm() < 1e-6;
  }
  return out;
}

}  // namespace tpcal::pipeline::diagnosis_internal
