// A candidate effect's columns seen through the complement of the base design (diagnosis.h,
// Frisch-Waugh): the directions the base model and the re-alignment do not absorb, the principal
// angles to the base design, and the map from a fit on the residual back to the candidate's
// coefficients. Internal to the diagnosis library.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "pipeline/diagnosis/diagnosis_candidates.h"

namespace tpcal::pipeline::diagnosis_internal {

// A candidate's columns (or two candidates' for a joint fit), each n long.
using Columns = std::vector<Eigen::Map<const Eigen::VectorXd>>;
Columns ColumnsOf(const CandidateColumns& c);
// Column norms (ZeroRoundingColumns applied).
Eigen::VectorXd ColumnNorms(const Columns& C);

// A candidate's columns C (n x p) seen through the complement of the span of Q (orthonormal,
// the base design). span(C) is orthonormalised first (relative rank tolerance 1e-10 on unit-norm
// columns); its directions whose principal angle to span(Q) has a sine below `tol` are absorbed.
// The kept directions give the basis U (n x k) of the fit on the residual; a fit z = U^T r maps
// back to C's coefficients x = B z (p x k, C's own units), cov(x) = sigma^2 B B^T.
struct Projected {
  Eigen::MatrixXd U, B;
  std::vector<bool> identifiable;
  int rank = 0;
  double max_sine = 0.0;  // of the principal angles to the base: the share of the most visible direction
  double rms_sine = 0.0;  // RMS over span(C)'s directions: the share of a typical signature
};

// `tol`: sine of the principal angle below which a direction is absorbed.
Projected ProjectCandidate(const Columns& C, const Eigen::MatrixXd& Q, double tol);

}  // namespace tpcal::pipeline::diagnosis_internal
