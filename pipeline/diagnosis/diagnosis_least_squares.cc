#include "pipeline/diagnosis/diagnosis_least_squares.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

#include "core/tall_svd.h"

namespace tpcal::pipeline::diagnosis_internal {
namespace {

constexpr double kMinLeverage = 1e-9;      // 1 - h below this: the point fits itself (PRESS huge)
constexpr double kRoundingColumn = 1e-10;  // see ZeroRoundingColumns

}  // namespace

Basis MakeBasis(const Eigen::MatrixXd& J, const Eigen::VectorXd& norms, double rel_tol, bool relative_to_largest) {
  Basis b;
  b.scale = norms;
  Eigen::MatrixXd Js = J;
  for (Eigen::Index j = 0; j < J.cols(); ++j) Js.col(j) = norms(j) > 0 ? Eigen::VectorXd(J.col(j) / norms(j)) : Eigen::VectorXd::Zero(J.rows());
  if (J.cols() == 0) {
    b.U.resize(J.rows(), 0);
    return b;
  }
  TallSvdResult svd = TallSvd(Js, /*compute_u=*/true);
  b.sigma = std::move(svd.sigma);
  b.V = std::move(svd.V);
  const double ref = relative_to_largest ? (b.sigma.size() ? b.sigma(0) : 0.0) : 1.0;
  for (Eigen::Index k = 0; k < b.sigma.size(); ++k)
    if (b.sigma(k) > rel_tol * ref && b.sigma(k) > 0) ++b.rank;
  b.U = svd.U.leftCols(b.rank);
  return b;
}

Eigen::VectorXd ZeroRoundingColumns(Eigen::VectorXd n) {
  const double largest = n.size() ? n.maxCoeff() : 0.0;
  for (Eigen::Index j = 0; j < n.size(); ++j)
    if (n(j) <= kRoundingColumn * largest) n(j) = 0.0;
  return n;
}
Eigen::VectorXd ColumnNorms(const Eigen::MatrixXd& J) {
  Eigen::VectorXd n(J.cols());
  for (Eigen::Index j = 0; j < J.cols(); ++j) n(j) = J.col(j).norm();
  return ZeroRoundingColumns(std::move(n));
}

void Solve(const Basis& b, const Eigen::VectorXd& y, double s2, Eigen::VectorXd* coef, Eigen::VectorXd* u,
           std::vector<bool>* identifiable) {
  const Eigen::Index p = b.scale.size();
  coef->setZero(p);
  u->setZero(p);
  identifiable->assign(static_cast<std::size_t>(p), true);
  if (p == 0) return;
  const Eigen::MatrixXd Vr = b.V.leftCols(b.rank);
  Eigen::VectorXd z = b.U.transpose() * y;
  for (int k = 0; k < b.rank; ++k) z(k) /= b.sigma(k);
  Eigen::VectorXd c = Vr * z;
  Eigen::MatrixXd W = Vr;
  for (int k = 0; k < b.rank; ++k) W.col(k) /= b.sigma(k);
  for (Eigen::Index j = 0; j < p; ++j) {
    const double s = b.scale(j) > 0 ? b.scale(j) : 1.0;
    (*coef)(j) = c(j) / s;
    (*u)(j) = std::sqrt(s2 * W.row(j).squaredNorm()) / s;
    const double null_part = b.rank < p ? b.V.row(j).tail(p - b.rank).norm() : 0.0;
    if (null_part > 1e-6 || b.scale(j) == 0) (*identifiable)[static_cast<std::size_t>(j)] = false;
  }
}

double FUpperTail(double f, double d1, double d2) {
  if (!(f > 0) || d1 <= 0 || d2 <= 0) return 1.0;
  const double a = 2.0 / (9.0 * d1), b = 2.0 / (9.0 * d2);
  const double c = std::cbrt(f);
  const double z = ((1.0 - b) * c - (1.0 - a)) / std::sqrt(a + b * c * c);
  return 0.5 * std::erfc(z / std::sqrt(2.0));
}

ChiSquareLaw SatterthwaiteLaw(int k, double sigma2_um2, const Eigen::MatrixXd& Z) {
  const double k_d = static_cast<double>(k);
  assert(Z.cols() == 0 || Z.rows() >= k);
  if (Z.cols() == 0 || Z.rows() == 0) return {k_d * sigma2_um2, k_d};
  const double tr_a = Z.squaredNorm();  // tr(Z Z^T)
  const double tr_a2 = Z.rows() <= Z.cols() ? (Z * Z.transpose()).squaredNorm() : (Z.transpose() * Z).squaredNorm();
  const double mean = k_d * sigma2_um2 + tr_a;
  const double half_var = k_d * sigma2_um2 * sigma2_um2 + 2.0 * sigma2_um2 * tr_a + tr_a2;
  return {mean, half_var > 0 ? mean * mean / half_var : k_d};
}

double EstimatedMeanDof(const ChiSquareLaw& law, int k, double sigma2_um2, double dof2) {
  const double noise = static_cast<double>(k) * sigma2_um2;
  return noise > 0 ? dof2 * (law.mean_um2 / noise) * (law.mean_um2 / noise) : dof2;
}

double Rms(const Eigen::VectorXd& r) { return r.size() ? std::sqrt(r.squaredNorm() / static_cast<double>(r.size())) : 0.0; }

Eigen::VectorXd Press(const Eigen::VectorXd& r, const Eigen::VectorXd& h) {
  Eigen::VectorXd e(r.size());
  for (Eigen::Index i = 0; i < r.size(); ++i) e(i) = r(i) / std::max(1.0 - h(i), kMinLeverage);
  return e;
}

Eigen::VectorXd RowSquaredNorms(const Eigen::MatrixXd& U) {
  Eigen::VectorXd h = Eigen::VectorXd::Zero(U.rows());
  if (U.cols() > 0) h = U.rowwise().squaredNorm();
  return h;
}

}  // namespace tpcal::pipeline::diagnosis_internal
