// The linear least squares of the diagnosis (diagnosis.h): an orthonormal basis of a design's
// column space, the fit on it with analytic uncertainties, leave-one-point-out residuals (PRESS)
// and the F-test tail. Display units throughout (um, urad); internal to the diagnosis library.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace tpcal::pipeline::diagnosis_internal {

// Orthonormal basis of the column space of J (columns scaled to unit norm first).
struct Basis {
  Eigen::MatrixXd U;        // n x r
  Eigen::MatrixXd V;        // p x p (scaled coordinates)
  Eigen::VectorXd sigma;    // p
  Eigen::VectorXd scale;    // p: column norms (0 for zero columns)
  int rank = 0;
};

// The basis of J with columns scaled by `norms`: singular values above rel_tol (times the largest
// when relative_to_largest) count towards the rank.
Basis MakeBasis(const Eigen::MatrixXd& J, const Eigen::VectorXd& norms, double rel_tol, bool relative_to_largest);

// Column norms; a column below kRoundingColumn x the largest is rounding of an exactly zero
// signature (e.g. E_Z0A on the flank-milled cone, 3e-15 um/um: Z slides the tool along its own
// axis) and gets norm 0 (not fitted, not identifiable): scaled to unit norm it would be a random
// direction, fitted with coefficients of 1e12 mm.
Eigen::VectorXd ZeroRoundingColumns(Eigen::VectorXd n);
Eigen::VectorXd ColumnNorms(const Eigen::MatrixXd& J);

// Coefficients (original column units) of the least-squares fit of y on the basis' columns,
// minimum-norm in scaled units, and their analytic standard uncertainties for residual variance s2.
void Solve(const Basis& b, const Eigen::VectorXd& y, double s2, Eigen::VectorXd* coef, Eigen::VectorXd* u,
           std::vector<bool>* identifiable);

// Upper tail of the F distribution (Paulson's normal approximation; adequate for d2 > 30).
double FUpperTail(double f, double d1, double d2);

// The law of a sum of squares of k components holding noise of variance sigma2_um2 each and a
// correlated part of covariance Z Z^T (Z: k x r, um; or m >= k rows, coordinates of a larger
// space whose columns lie in the components' k-dimensional subspace, e.g. a residual's): c chi2_d
// with its mean and variance (Satterthwaite), returned as the mean c d (um^2) and d. Z with no
// column: k sigma2, k.
struct ChiSquareLaw {
  double mean_um2 = 0.0;
  double dof = 0.0;
};
ChiSquareLaw SatterthwaiteLaw(int k, double sigma2_um2, const Eigen::MatrixXd& Z);

// The degrees of freedom of `law`'s mean as the denominator of an F ratio when only its noise
// part k sigma2_um2 is estimated (on dof2) and the correlated part is known: the mean's relative
// variance is sigma2's scaled by (k sigma2 / mean)^2, so dof2 (mean / k sigma2)^2 (dof2 without
// Z). Exact for an independent sigma2 (the neighbour sigma); where sigma2 is the residual's own
// estimate, which also holds the reference's leftover variance off the directions tested, its
// dof2 is a little lower than taken and the test a little permissive.
double EstimatedMeanDof(const ChiSquareLaw& law, int k, double sigma2_um2, double dof2);

// Root mean square (0 for an empty vector).
double Rms(const Eigen::VectorXd& r);

// Leave-one-point-out residuals r_i / (1 - h_ii) of residuals r with leverages h.
Eigen::VectorXd Press(const Eigen::VectorXd& r, const Eigen::VectorXd& h);

// Leverages of an orthonormal basis: the squared norm of each row (zeros for no column).
Eigen::VectorXd RowSquaredNorms(const Eigen::MatrixXd& U);

}  // namespace tpcal::pipeline::diagnosis_internal
