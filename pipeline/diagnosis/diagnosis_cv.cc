#include "pipeline/diagnosis/diagnosis_cv.h"

#include <Eigen/Eigenvalues>
#include <cassert>
#include <cmath>

namespace tpcal::pipeline {
namespace {

Eigen::MatrixXd Rows(const Eigen::MatrixXd& Q, const std::vector<Eigen::Index>& rows) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(rows.size()), Q.cols());
  if (Q.cols() == 0) return out;  // a row of no column has no data to point at (UBSan)
  for (std::size_t k = 0; k < rows.size(); ++k) out.row(static_cast<Eigen::Index>(k)) = Q.row(rows[k]);
  return out;
}

}  // namespace

double GroupCvResult::RmsOver(const std::vector<bool>& mask) const {
  assert(mask.size() == holdable.size());
  double ss = 0.0;
  long n = 0;
  for (std::size_t g = 0; g < mask.size(); ++g) {
    if (!mask[g]) continue;
    assert(holdable[g]);
    ss += ss_by_group[g];
    n += n_by_group[g];
  }
  return n > 0 ? std::sqrt(ss / static_cast<double>(n)) : 0.0;
}

GroupCrossValidation::GroupCrossValidation(const Eigen::MatrixXd& Q0, const std::vector<int>& group_of_point,
                                           int n_groups, double holdout_tolerance)
    : Q0_(Q0), rows_(static_cast<std::size_t>(n_groups)), tolerance_(holdout_tolerance) {
  assert(static_cast<Eigen::Index>(group_of_point.size()) == Q0.rows());
  for (std::size_t i = 0; i < group_of_point.size(); ++i) {
    assert(group_of_point[i] >= 0 && group_of_point[i] < n_groups);
    rows_[static_cast<std::size_t>(group_of_point[i])].push_back(static_cast<Eigen::Index>(i));
  }
  gram0_.reserve(rows_.size());
  for (const auto& r : rows_) {
    const Eigen::MatrixXd Qg = Rows(Q0_, r);
    gram0_.push_back(Qg.transpose() * Qg);
  }
}

GroupCvResult GroupCrossValidation::Evaluate(const Eigen::VectorXd& residual) const {
  return Evaluate(Eigen::MatrixXd(Q0_.rows(), 0), residual);
}

GroupCvResult GroupCrossValidation::Evaluate(const Eigen::MatrixXd& Q1, const Eigen::VectorXd& residual) const {
  assert(Q1.rows() == Q0_.rows() && residual.size() == Q0_.rows());
  const Eigen::Index p0 = Q0_.cols(), p1 = Q1.cols(), p = p0 + p1;
  GroupCvResult out;
  out.heldout_residual = Eigen::VectorXd::Zero(residual.size());
  out.holdable.assign(rows_.size(), false);
  out.min_information.assign(rows_.size(), 0.0);
  out.ss_by_group.assign(rows_.size(), 0.0);
  out.n_by_group.assign(rows_.size(), 0);
  for (std::size_t g = 0; g < rows_.size(); ++g) {
    const auto& r = rows_[g];
    if (r.empty()) continue;
    const auto ng = static_cast<Eigen::Index>(r.size());
    // A group whose points are consecutive (a scan stores each feature's points together) is read
    // in place; otherwise its rows are gathered.
    const bool contiguous = r.back() - r.front() + 1 == ng;
    Eigen::MatrixXd Qg(ng, p);
    if (contiguous) {
      Qg.leftCols(p0) = Q0_.middleRows(r.front(), ng);
      if (p1 > 0) Qg.rightCols(p1) = Q1.middleRows(r.front(), ng);
    } else {
      Qg.leftCols(p0) = Rows(Q0_, r);
      if (p1 > 0) Qg.rightCols(p1) = Rows(Q1, r);
    }
    // M_G = I - Q_G^T Q_G, with Q0's block from the constructor.
    Eigen::MatrixXd M = -Eigen::MatrixXd::Identity(p, p);
    M.topLeftCorner(p0, p0) += gram0_[g];
    if (p1 > 0) {
      const Eigen::MatrixXd Q1g = Qg.rightCols(p1);
      M.topRightCorner(p0, p1) = Qg.leftCols(p0).transpose() * Q1g;
      M.bottomLeftCorner(p1, p0) = M.topRightCorner(p0, p1).transpose();
      M.bottomRightCorner(p1, p1) += Q1g.transpose() * Q1g;
    }
    M = -M;
    Eigen::VectorXd eg(ng);
    if (contiguous)
      eg = residual.segment(r.front(), ng);
    else
      for (Eigen::Index k = 0; k < ng; ++k) eg(k) = residual(r[static_cast<std::size_t>(k)]);
    double lambda_min = 1.0;
    Eigen::VectorXd cv = eg;
    if (p > 0) {
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(M);
      lambda_min = es.eigenvalues()(0);  // ascending
      if (lambda_min >= tolerance_) {
        Eigen::VectorXd v = es.eigenvectors().transpose() * (Qg.transpose() * eg);
        v.array() /= es.eigenvalues().array();
        cv += Qg * (es.eigenvectors() * v);
      }
    }
    out.min_information[g] = lambda_min;
    out.n_by_group[g] = static_cast<int>(ng);
    if (lambda_min < tolerance_) continue;
    out.holdable[g] = true;
    if (contiguous)
      out.heldout_residual.segment(r.front(), ng) = cv;
    else
      for (Eigen::Index k = 0; k < ng; ++k) out.heldout_residual(r[static_cast<std::size_t>(k)]) = cv(k);
    out.ss_by_group[g] = cv.squaredNorm();
  }
  return out;
}

}  // namespace tpcal::pipeline
