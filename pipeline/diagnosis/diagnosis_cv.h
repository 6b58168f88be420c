// Leave-one-group-out cross-validation of a linear least-squares fit (diagnosis.h): the residual
// each group of points (a measured feature) gets when the model is fitted without that group.
//
// Design. The fit is given in orthonormal form: Q (n x p, Q^T Q = I) spans the design's column
// space (e.g. the thin U of its SVD, truncated at its rank), so the hat matrix is H = Q Q^T and the
// in-sample residual is e = y - Q Q^T y. For a group G of n_G points the held-out residual
// (y_G minus the prediction of the fit on the other points) is
//   e_G(-G) = (I - H_GG)^-1 e_G = e_G + Q_G M_G^-1 Q_G^T e_G,   M_G = I - Q_G^T Q_G   (Woodbury),
// p x p per group, O(n_G p^2), no n_G x n_G inverse. M_G = Q_{-G}^T Q_{-G} is the information the
// other groups carry (the full design carries I): its eigenvalues lie in [0, 1].
// A group is not holdable when the smallest eigenvalue of M_G is below `holdout_tolerance`: its
// points alone (or almost alone) determine a direction of the model, so the fit without it
// cannot predict it (exactly rank-deficient at 0; below the tolerance the prediction's noise is
// amplified by more than 1 / sqrt(tolerance)). Such groups get no held-out residual and are
// left out of the CV sums.
//
// Two blocks: Q = [Q0, Q1] with Q1 orthonormal and orthogonal to Q0 (the base design and a
// candidate's columns projected on its complement, diagnosis.cc). Q0's per-group Gram matrices
// are computed once in the constructor; Evaluate(Q1, e) adds Q1's blocks, O(n p1 (p0 + p1)).
// Deterministic (no randomness, fixed summation order).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace tpcal::pipeline {

struct GroupCvResult {
  Eigen::VectorXd heldout_residual;  // n: e_G(-G) for points of holdable groups, 0 elsewhere
  std::vector<bool> holdable;        // per group
  std::vector<double> min_information;  // per group: smallest eigenvalue of M_G (1 = no loss)
  std::vector<double> ss_by_group;      // per group: sum of squared held-out residuals (0 if not holdable)
  std::vector<int> n_by_group;          // per group: points
  // Root mean square of the held-out residuals over the points of the groups with mask[g] true
  // (each must be holdable here); 0 when no point is counted.
  double RmsOver(const std::vector<bool>& mask) const;
  // The same over every holdable group.
  double Rms() const { return RmsOver(holdable); }
};

class GroupCrossValidation {
 public:
  // Q0: n x p0 orthonormal columns. group_of_point: n entries in [0, n_groups).
  GroupCrossValidation(const Eigen::MatrixXd& Q0, const std::vector<int>& group_of_point, int n_groups,
                       double holdout_tolerance);

  // The fit on Q0 alone; `residual` = y - Q0 Q0^T y.
  GroupCvResult Evaluate(const Eigen::VectorXd& residual) const;
  // The joint fit on [Q0, Q1] (Q1: n x p1, orthonormal, orthogonal to Q0); residual of that fit.
  GroupCvResult Evaluate(const Eigen::MatrixXd& Q1, const Eigen::VectorXd& residual) const;

  int n_groups() const { return static_cast<int>(rows_.size()); }
  const std::vector<Eigen::Index>& rows(int g) const { return rows_[static_cast<std::size_t>(g)]; }

 private:
  Eigen::MatrixXd Q0_;                           // a copy (n x p0)
  std::vector<std::vector<Eigen::Index>> rows_;  // point indices of each group, ascending
  std::vector<Eigen::MatrixXd> gram0_;           // Q0_G^T Q0_G per group
  double tolerance_;
};

}  // namespace tpcal::pipeline
