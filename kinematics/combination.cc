#include <Eigen/SVD>
#include <cmath>
#include <sstream>

#include "kinematics/internal/combination.h"

namespace tpcal::kinematics::internal {

std::string FormatCombination(const std::vector<std::string>& names, const std::vector<double>& c) {
  std::ostringstream os;
  bool first = true;
  for (std::size_t k = 0; k < names.size() && k < c.size(); ++k) {
    const double v = c[k];
    if (std::abs(v) < 1e-6) continue;  // 1e-6 um per urad: below any effect a report could show
    const double mag = std::abs(v);
    if (first) {
      if (v < 0) os << "-";
    } else {
      os << (v < 0 ? " - " : " + ");
    }
    if (std::abs(mag - 1.0) > 1e-6) {
      std::ostringstream num;
      num.precision(4);
      num << mag;
      os << num.str() << " ";
    }
    os << names[k];
    first = false;
  }
  return os.str();
}

void NormaliseCombination(Eigen::VectorXd* c) {
  Eigen::Index imax = 0;
  c->cwiseAbs().maxCoeff(&imax);
  const double m = (*c)(imax);
  if (m != 0.0) *c /= m;
  for (Eigen::Index k = 0; k < c->size(); ++k)
    if (std::abs((*c)(k)) < 1e-10) (*c)(k) = 0.0;
}

std::vector<Eigen::VectorXd> EstimableCombinations(const Eigen::MatrixXd& null_space, const std::vector<int>& subset) {
  std::vector<Eigen::VectorXd> out;
  const auto s = static_cast<Eigen::Index>(subset.size());
  if (s == 0) return out;
  Eigen::MatrixXd NS(s, null_space.cols());
  for (Eigen::Index a = 0; a < s; ++a) NS.row(a) = null_space.row(subset[a]);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(NS.transpose(), Eigen::ComputeFullV);
  const Eigen::Index rank = (svd.singularValues().array() > 1e-9).count();
  // Basis of the estimable combinations (the orthogonal complement of the null space within the
  // subset), brought to reduced row echelon form so each combination involves few parameters
  // (e.g. "dx_CR(0) - 0.4057 beta_ZX" rather than a dense SVD vector).
  const Eigen::Index m = s - rank;
  if (m <= 0) return out;
  Eigen::MatrixXd B(m, s);
  for (Eigen::Index j = rank; j < s; ++j) B.row(j - rank) = svd.matrixV().col(j).transpose();
  Eigen::Index row = 0;
  for (Eigen::Index col = 0; col < s && row < m; ++col) {
    Eigen::Index piv = row;
    B.col(col).segment(row, m - row).cwiseAbs().maxCoeff(&piv);
    piv += row;
    if (std::abs(B(piv, col)) < 1e-9) continue;
    B.row(row).swap(B.row(piv));
    B.row(row) /= B(row, col);
    for (Eigen::Index r = 0; r < m; ++r)
      if (r != row) B.row(r) -= B(r, col) * B.row(row);
    ++row;
  }
  for (Eigen::Index j = 0; j < m; ++j) {
    Eigen::VectorXd c = B.row(j).transpose();
    NormaliseCombination(&c);
    Eigen::VectorXd full = Eigen::VectorXd::Zero(null_space.rows());
    for (Eigen::Index a = 0; a < s; ++a) full(subset[a]) = c(a);
    out.push_back(full);
  }
  return out;
}

}  // namespace tpcal::kinematics::internal
